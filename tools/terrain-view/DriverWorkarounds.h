// DriverWorkarounds: what the viewer does only because of a driver or system library, each
// with its reason, in one place (../shared/STYLE.md, "Resources").
#pragma once

namespace terrain::view {

/// Mesa's DRI driver (e.g. swrast_dri.so) keeps a few blocks it allocated reachable only
/// from its own globals, and glfwTerminate unloads it when the X display closes: the blocks
/// are then unreachable and LeakSanitizer reports them at exit, with stack frames in a
/// module that is gone (so no suppression can name it). In AddressSanitizer builds this
/// pins the loaded DRI driver for the life of the process — which is how an EGL context
/// behaves anyway — so the leak check sees them referenced; elsewhere it does nothing.
/// Call after the GL context exists.
void keepGlDriverLoadedForLeakChecks();

}  // namespace terrain::view
