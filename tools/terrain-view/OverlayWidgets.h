// OverlayWidgets: the few Dear ImGui idioms every part of terrain-view's overlay draws with
// (dimmed labels, a warning colour, small buttons), so the sections the surfaces draw look
// like the rest of the panel. Inside ImGui's frame only.
#pragma once

#include <imgui.h>

#include <numbers>
#include <string>

namespace terrain::view::overlay {

inline const ImVec4 kDim{0.62f, 0.66f, 0.72f, 1.0f};
inline const ImVec4 kWarn{1.0f, 0.62f, 0.30f, 1.0f};
inline const ImVec4 kGood{0.55f, 0.85f, 0.55f, 1.0f};

inline double degrees(double radians) { return radians * 180.0 / std::numbers::pi; }

inline void text(const std::string& s) { ImGui::TextUnformatted(s.c_str()); }

inline void dimText(const std::string& s) {
    ImGui::PushStyleColor(ImGuiCol_Text, kDim);
    ImGui::TextUnformatted(s.c_str());
    ImGui::PopStyleColor();
}

inline bool button(const char* label) { return ImGui::SmallButton(label); }

/// A number field of the jump section; true when Enter was pressed in it.
inline bool jumpField(const char* label, double* value, const char* format) {
    ImGui::SetNextItemWidth(-120.0f);
    ImGui::InputDouble(label, value, 0.0, 0.0, format);
    return ImGui::IsItemDeactivated() &&
           (ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Enter)) ||
            ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_KeyPadEnter)));
}

}  // namespace terrain::view::overlay
