// KeyBindings: the viewer's one-shot actions and the keys that trigger them, in one table
// that the key handler, the overlay's key list and --help all read, so they cannot drift
// apart (docs/viewer.md lists the same table).
#pragma once

#include <optional>
#include <span>
#include <string_view>

namespace terrain::view {

enum class ViewerAction {
    ToggleOverlay,
    Screenshot,
    ToggleFreezeLod,
    ToggleTelemetryLog,
    ToggleOrbit,
    ToggleRecording,
    ViewShaded,
    ViewLevel,
    ViewTessFactor,
    ToggleWireframe,
    ToggleSkirts,
    ToggleFog,
    ToggleVsync,
    ToggleFloor,
    PlayPause,
    RestartPath,
    Home,
    FinerError,
    CoarserError,
    OpenJump,
    Quit,
};

struct KeyBinding {
    ViewerAction action;
    int key;                ///< GLFW_KEY_*
    int alternateKey;       ///< GLFW_KEY_* or GLFW_KEY_UNKNOWN
    std::string_view keys;  ///< as shown to the user, e.g. "F12 / P"
    std::string_view description;
};

/// Every binding, in the order the overlay and the docs list them.
std::span<const KeyBinding> keyBindings();

/// The action bound to a GLFW key, if any.
std::optional<ViewerAction> actionForKey(int glfwKey);

/// Keys held for flight, mouse and wheel, as shown to the user (key, what it does).
struct HeldControl {
    std::string_view keys;
    std::string_view description;
};
std::span<const HeldControl> heldControls();

}  // namespace terrain::view
