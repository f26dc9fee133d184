// The key table of the viewer.
#include "KeyBindings.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <array>

namespace terrain::view {
namespace {

constexpr int kNone = GLFW_KEY_UNKNOWN;

constexpr std::array kBindings = {
    KeyBinding{ViewerAction::ToggleOverlay, GLFW_KEY_F1, kNone, "F1", "show / hide the overlay"},
    KeyBinding{ViewerAction::Screenshot, GLFW_KEY_F12, GLFW_KEY_P, "F12 / P",
               "screenshot (PNG, what the window shows)"},
    KeyBinding{ViewerAction::ToggleFreezeLod, GLFW_KEY_L, kNone, "L",
               "freeze the LOD cut, then fly out to inspect it"},
    KeyBinding{ViewerAction::ToggleTelemetryLog, GLFW_KEY_T, kNone, "T",
               "start / stop the telemetry CSV log"},
    KeyBinding{ViewerAction::ToggleOrbit, GLFW_KEY_O, kNone, "O",
               "orbit the terrain point at the centre / back to flying"},
    KeyBinding{ViewerAction::ToggleRecording, GLFW_KEY_R, kNone, "R",
               "start / stop recording a camera path"},
    KeyBinding{ViewerAction::ViewShaded, GLFW_KEY_1, kNone, "1", "shaded"},
    KeyBinding{ViewerAction::ViewLevel, GLFW_KEY_2, kNone, "2", "colour by patch level"},
    KeyBinding{ViewerAction::ViewTessFactor, GLFW_KEY_3, kNone, "3",
               "colour by tessellation factor"},
    KeyBinding{ViewerAction::ToggleWireframe, GLFW_KEY_4, kNone, "4", "wireframe"},
    KeyBinding{ViewerAction::ToggleSkirts, GLFW_KEY_5, kNone, "5", "skirts on / off"},
    KeyBinding{ViewerAction::ToggleFog, GLFW_KEY_F, kNone, "F", "fog on / off"},
    KeyBinding{ViewerAction::ToggleVsync, GLFW_KEY_V, kNone, "V", "vsync on / off"},
    KeyBinding{ViewerAction::ToggleFloor, GLFW_KEY_G, kNone, "G", "keep above the ground on / off"},
    KeyBinding{ViewerAction::FinerError, GLFW_KEY_LEFT_BRACKET, GLFW_KEY_KP_SUBTRACT, "[",
               "finer: error threshold eps / 1.25"},
    KeyBinding{ViewerAction::CoarserError, GLFW_KEY_RIGHT_BRACKET, GLFW_KEY_KP_ADD, "]",
               "coarser: error threshold eps × 1.25"},
    KeyBinding{ViewerAction::PlayPause, GLFW_KEY_SPACE, kNone, "Space",
               "play / pause the camera path"},
    KeyBinding{ViewerAction::RestartPath, GLFW_KEY_BACKSPACE, kNone, "Backspace",
               "play the camera path from the start"},
    KeyBinding{ViewerAction::Home, GLFW_KEY_H, GLFW_KEY_HOME, "H / Home",
               "back to the view of the whole DEM"},
    KeyBinding{ViewerAction::OpenJump, GLFW_KEY_J, kNone, "J", "jump to coordinates"},
    KeyBinding{ViewerAction::Quit, GLFW_KEY_ESCAPE, kNone, "Esc", "quit"},
};

constexpr std::array kHeld = {
    HeldControl{"W A S D / arrows", "fly forward, left, back, right (orbit: move the pivot)"},
    HeldControl{"Q / E", "down / up (orbit: closer / further)"},
    HeldControl{"Shift / Ctrl", "5× faster / 5× slower"},
    HeldControl{"right or left drag", "look around (orbit: turn around the pivot)"},
    HeldControl{"middle click", "orbit the clicked point"},
    HeldControl{"wheel", "fly speed (orbit: zoom)"},
};

}  // namespace

std::span<const KeyBinding> keyBindings() { return kBindings; }

std::optional<ViewerAction> actionForKey(int glfwKey) {
    if (glfwKey == GLFW_KEY_UNKNOWN) return std::nullopt;
    for (const KeyBinding& binding : kBindings) {
        if (binding.key == glfwKey || binding.alternateKey == glfwKey) return binding.action;
    }
    return std::nullopt;
}

std::span<const HeldControl> heldControls() { return kHeld; }

}  // namespace terrain::view
