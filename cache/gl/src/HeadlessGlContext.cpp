// Headless OpenGL 4.5 core through EGL: EGL_EXT_platform_device first (on NVIDIA this is
// the GPU; Mesa lists its hardware devices and a software one), then
// EGL_MESA_platform_surfaceless. No surface is ever made (EGL_KHR_surfaceless_context).
#include "terrain/gl/HeadlessGlContext.h"

#include "terrain/gl/DriverWorkarounds.h"

// epoxy/gl.h must precede the EGL headers: it declares the khrplatform types itself and
// conflicts with them when EGL's copy came first.
#include <epoxy/gl.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

namespace terrain::gl {

struct HeadlessGlContext::Egl {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    std::string platform;
    std::string detail;

    Egl() = default;
    Egl(const Egl&) = delete;
    Egl& operator=(const Egl&) = delete;
    ~Egl();
};

namespace {

/// EGL displays are never terminated; each is initialised once and kept until the process
/// ends (eglInitialize on an initialised display is a no-op, and an EGLDisplay is a
/// process-wide singleton per platform and device anyway). Reasons:
/// - eglTerminate ends every context of the display, and two HeadlessGlContexts on one
///   platform share the display;
/// - Mesa unloads its driver in eglTerminate, so the next context pays a full driver load
///   again (slow for llvmpipe, which initialises LLVM), and the driver's static
///   allocations, unreachable once its data is unmapped, become LeakSanitizer reports
///   that cannot be suppressed by module name (the module is gone).
constexpr bool kKeepEglDisplaysInitialised = true;

const char* eglErrorName(EGLint error) {
    switch (error) {
        case EGL_SUCCESS:
            return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED:
            return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ACCESS:
            return "EGL_BAD_ACCESS";
        case EGL_BAD_ALLOC:
            return "EGL_BAD_ALLOC";
        case EGL_BAD_ATTRIBUTE:
            return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONFIG:
            return "EGL_BAD_CONFIG";
        case EGL_BAD_CONTEXT:
            return "EGL_BAD_CONTEXT";
        case EGL_BAD_CURRENT_SURFACE:
            return "EGL_BAD_CURRENT_SURFACE";
        case EGL_BAD_DISPLAY:
            return "EGL_BAD_DISPLAY";
        case EGL_BAD_MATCH:
            return "EGL_BAD_MATCH";
        case EGL_BAD_NATIVE_PIXMAP:
            return "EGL_BAD_NATIVE_PIXMAP";
        case EGL_BAD_NATIVE_WINDOW:
            return "EGL_BAD_NATIVE_WINDOW";
        case EGL_BAD_PARAMETER:
            return "EGL_BAD_PARAMETER";
        case EGL_BAD_SURFACE:
            return "EGL_BAD_SURFACE";
        case EGL_CONTEXT_LOST:
            return "EGL_CONTEXT_LOST";
        case EGL_BAD_DEVICE_EXT:
            return "EGL_BAD_DEVICE_EXT";
        default:
            return "unknown EGL error";
    }
}

std::string eglFailure(const char* call) {
    return std::string(call) + " failed (" + eglErrorName(eglGetError()) + ")";
}

/// Whole-token search in an EGL extension string (which may be null).
bool hasExtension(const char* extensions, std::string_view name) {
    if (extensions == nullptr) {
        return false;
    }
    std::string_view list(extensions);
    while (!list.empty()) {
        const std::size_t end = list.find(' ');
        if (list.substr(0, end) == name) {
            return true;
        }
        if (end == std::string_view::npos) {
            break;
        }
        list.remove_prefix(end + 1);
    }
    return false;
}

/// The thread's current EGL binding, to put back after touching another context.
struct CurrentEgl {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLSurface draw = EGL_NO_SURFACE;
    EGLSurface read = EGL_NO_SURFACE;
    EGLContext context = EGL_NO_CONTEXT;

    static CurrentEgl capture() {
        eglBindAPI(EGL_OPENGL_API);
        return {eglGetCurrentDisplay(), eglGetCurrentSurface(EGL_DRAW),
                eglGetCurrentSurface(EGL_READ), eglGetCurrentContext()};
    }
};

struct EglEntryPoints {
    PFNEGLGETPLATFORMDISPLAYEXTPROC getPlatformDisplay = nullptr;
    PFNEGLQUERYDEVICESEXTPROC queryDevices = nullptr;
    PFNEGLQUERYDEVICESTRINGEXTPROC queryDeviceString = nullptr;

    static EglEntryPoints load() {
        EglEntryPoints entryPoints;
        entryPoints.getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
            eglGetProcAddress("eglGetPlatformDisplayEXT"));
        entryPoints.queryDevices =
            reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
        entryPoints.queryDeviceString = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
            eglGetProcAddress("eglQueryDeviceStringEXT"));
        return entryPoints;
    }
};

/// Makes a 4.5 core context on `display` and makes it current, or says why not.
Result<std::unique_ptr<HeadlessGlContext::Egl>> createOnDisplay(EGLDisplay display,
                                                                bool debugContext,
                                                                std::string platform,
                                                                std::string detail) {
    if (display == EGL_NO_DISPLAY) {
        return Error{eglFailure("eglGetPlatformDisplayEXT")};
    }
    EGLint eglMajor = 0;
    EGLint eglMinor = 0;
    if (eglInitialize(display, &eglMajor, &eglMinor) != EGL_TRUE) {
        return Error{eglFailure("eglInitialize")};
    }
    // Displays stay initialised until the process ends: see kKeepEglDisplaysInitialised.
    auto egl = std::make_unique<HeadlessGlContext::Egl>();
    egl->display = display;

    const char* vendor = eglQueryString(display, EGL_VENDOR);
    egl->platform = std::move(platform);
    egl->detail = "EGL " + std::to_string(eglMajor) + "." + std::to_string(eglMinor) + " (" +
                  (vendor != nullptr ? vendor : "unknown vendor") + ")" +
                  (detail.empty() ? "" : ", " + detail);

    const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
    if (!hasExtension(extensions, "EGL_KHR_surfaceless_context")) {
        return Error{"EGL_KHR_surfaceless_context missing"};
    }
    const bool egl15 = eglMajor > 1 || (eglMajor == 1 && eglMinor >= 5);
    if (!egl15 && !hasExtension(extensions, "EGL_KHR_create_context")) {
        return Error{"EGL " + std::to_string(eglMajor) + "." + std::to_string(eglMinor) +
                     " without EGL_KHR_create_context cannot ask for a core profile"};
    }
    if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) {
        return Error{eglFailure("eglBindAPI(EGL_OPENGL_API)")};
    }

    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!hasExtension(extensions, "EGL_KHR_no_config_context")) {
        // Surface type 0 matches every config: no surface is ever created.
        const EGLint configAttributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0,
                                           EGL_NONE};
        EGLint count = 0;
        if (eglChooseConfig(display, configAttributes, &config, 1, &count) != EGL_TRUE ||
            count < 1) {
            return Error{count < 1 && eglGetError() == EGL_SUCCESS
                             ? std::string("eglChooseConfig found no OpenGL config")
                             : eglFailure("eglChooseConfig")};
        }
    }

    std::vector<EGLint> contextAttributes = {
        EGL_CONTEXT_MAJOR_VERSION,       kRequiredGlMajor,
        EGL_CONTEXT_MINOR_VERSION,       kRequiredGlMinor,
        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT};
    if (debugContext) {
        // EGL 1.5 has its own attribute; EGL 1.4 carries the flag in EGL_CONTEXT_FLAGS_KHR.
        contextAttributes.push_back(egl15 ? EGL_CONTEXT_OPENGL_DEBUG : EGL_CONTEXT_FLAGS_KHR);
        contextAttributes.push_back(egl15 ? EGL_TRUE : EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR);
    }
    contextAttributes.push_back(EGL_NONE);
    egl->context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttributes.data());
    if (egl->context == EGL_NO_CONTEXT) {
        return Error{eglFailure(debugContext ? "eglCreateContext(OpenGL 4.5 core, debug)"
                                             : "eglCreateContext(OpenGL 4.5 core)")};
    }
    if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, egl->context) != EGL_TRUE) {
        return Error{eglFailure("eglMakeCurrent(no surface)")};
    }

    // Trust but verify: a driver may hand out a lower version than asked for.
    GLint glMajor = 0;
    GLint glMinor = 0;
    GLint profile = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &glMajor);
    glGetIntegerv(GL_MINOR_VERSION, &glMinor);
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    const bool versionOk =
        glMajor > kRequiredGlMajor || (glMajor == kRequiredGlMajor && glMinor >= kRequiredGlMinor);
    if (!versionOk || (profile & GL_CONTEXT_CORE_PROFILE_BIT) == 0) {
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        return Error{"got OpenGL " + std::to_string(glMajor) + "." + std::to_string(glMinor) +
                     ((profile & GL_CONTEXT_CORE_PROFILE_BIT) != 0 ? " core" : " (not core)") +
                     ", need 4.5 core"};
    }
    return egl;
}

struct Attempts {
    std::vector<std::string> failures;

    void fail(std::string_view what, const std::string& why) {
        failures.push_back(std::string(what) + ": " + why);
    }
};

/// A current context from the first EGL device that gives one, or null (with the reasons
/// in `attempts`).
std::unique_ptr<HeadlessGlContext::Egl> tryDevicePlatform(const EglEntryPoints& entryPoints,
                                                          const char* clientExtensions,
                                                          bool debugContext, Attempts& attempts) {
    constexpr std::string_view kName = "egl-device";
    for (const char* needed : {"EGL_EXT_platform_base", "EGL_EXT_platform_device"}) {
        if (!hasExtension(clientExtensions, needed)) {
            attempts.fail(kName, std::string("client extension ") + needed + " missing");
            return nullptr;
        }
    }
    if (entryPoints.queryDevices == nullptr || entryPoints.getPlatformDisplay == nullptr) {
        attempts.fail(kName, "eglQueryDevicesEXT or eglGetPlatformDisplayEXT not found");
        return nullptr;
    }
    EGLint count = 0;
    if (entryPoints.queryDevices(0, nullptr, &count) != EGL_TRUE) {
        attempts.fail(kName, eglFailure("eglQueryDevicesEXT"));
        return nullptr;
    }
    std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
    if (count == 0 || entryPoints.queryDevices(count, devices.data(), &count) != EGL_TRUE) {
        attempts.fail(
            kName, count == 0 ? std::string("no EGL devices") : eglFailure("eglQueryDevicesEXT"));
        return nullptr;
    }
    devices.resize(static_cast<std::size_t>(count));

    struct Candidate {
        EGLDeviceEXT device;
        std::string description;
        bool software;
    };
    std::vector<Candidate> candidates;
    for (std::size_t i = 0; i < devices.size(); ++i) {
        const char* deviceExtensions =
            entryPoints.queryDeviceString != nullptr
                ? entryPoints.queryDeviceString(devices[i], EGL_EXTENSIONS)
                : nullptr;
        const bool software = hasExtension(deviceExtensions, "EGL_MESA_device_software");
        std::string file;
        if (!software && hasExtension(deviceExtensions, "EGL_EXT_device_drm")) {
            const char* path = entryPoints.queryDeviceString(devices[i], EGL_DRM_DEVICE_FILE_EXT);
            file = path != nullptr ? path : "";
        }
        candidates.push_back({devices[i],
                              "device " + std::to_string(i) + " of " +
                                  std::to_string(devices.size()) + " (" +
                                  (software       ? std::string("software")
                                   : file.empty() ? "hardware"
                                                  : file) +
                                  ")",
                              software});
    }
    // A real GPU beats a software rasteriser when both are listed (Mesa lists its
    // software device next to hardware ones; NVIDIA's devices come through glvnd too).
    std::stable_partition(candidates.begin(), candidates.end(),
                          [](const Candidate& candidate) { return !candidate.software; });
    for (const Candidate& candidate : candidates) {
        EGLDisplay display =
            entryPoints.getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, candidate.device, nullptr);
        auto egl =
            createOnDisplay(display, debugContext, std::string(kName), candidate.description);
        if (egl) {
            return std::move(egl).value();
        }
        attempts.fail(std::string(kName) + " " + candidate.description, egl.error().message);
    }
    return nullptr;
}

/// A current context from Mesa's surfaceless platform, or null (reasons in `attempts`).
std::unique_ptr<HeadlessGlContext::Egl> trySurfacelessPlatform(const EglEntryPoints& entryPoints,
                                                               const char* clientExtensions,
                                                               bool debugContext,
                                                               Attempts& attempts) {
    constexpr std::string_view kName = "egl-surfaceless";
    for (const char* needed : {"EGL_EXT_platform_base", "EGL_MESA_platform_surfaceless"}) {
        if (!hasExtension(clientExtensions, needed)) {
            attempts.fail(kName, std::string("client extension ") + needed + " missing");
            return nullptr;
        }
    }
    if (entryPoints.getPlatformDisplay == nullptr) {
        attempts.fail(kName, "eglGetPlatformDisplayEXT not found");
        return nullptr;
    }
    EGLDisplay display =
        entryPoints.getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    auto egl = createOnDisplay(display, debugContext, std::string(kName), "Mesa surfaceless");
    if (!egl) {
        attempts.fail(kName, egl.error().message);
        return nullptr;
    }
    return std::move(egl).value();
}

}  // namespace

HeadlessGlContext::Egl::~Egl() {
    if (context != EGL_NO_CONTEXT) {
        eglDestroyContext(display, context);
    }
    static_assert(kKeepEglDisplaysInitialised, "eglTerminate is never called");
}

namespace {

/// "auto", "device", "surfaceless".
std::string_view eglPlatformName(EglPlatform platform) {
    switch (platform) {
        case EglPlatform::Automatic:
            return "auto";
        case EglPlatform::Device:
            return "device";
        case EglPlatform::Surfaceless:
            return "surfaceless";
    }
    return "unknown";
}

}  // namespace

Result<EglPlatform> parseEglPlatform(std::string_view text) {
    for (EglPlatform platform :
         {EglPlatform::Automatic, EglPlatform::Device, EglPlatform::Surfaceless}) {
        if (text == eglPlatformName(platform)) {
            return platform;
        }
    }
    return Error{"unknown EGL platform '" + std::string(text) +
                 "': use device, surfaceless or auto"};
}

Result<std::unique_ptr<HeadlessGlContext>> HeadlessGlContext::create(
    const HeadlessGlOptions& options) {
    EglPlatform platform = options.platform;
    if (platform == EglPlatform::Automatic) {
        if (const char* value = std::getenv("TERRAIN_EGL_PLATFORM");
            value != nullptr && value[0] != '\0') {
            auto parsed = parseEglPlatform(value);
            if (!parsed) {
                return Error{"TERRAIN_EGL_PLATFORM: " + parsed.error().message};
            }
            platform = parsed.value();
        }
    }

    // Failed attempts may leave no context current; a caller's context is put back then.
    const CurrentEgl previous = CurrentEgl::capture();
    const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    const EglEntryPoints entryPoints = EglEntryPoints::load();
    Attempts attempts;
    std::unique_ptr<Egl> egl;
    if (platform == EglPlatform::Automatic || platform == EglPlatform::Device) {
        egl = tryDevicePlatform(entryPoints, clientExtensions, options.debugContext, attempts);
    }
    if (!egl && (platform == EglPlatform::Automatic || platform == EglPlatform::Surfaceless)) {
        egl = trySurfacelessPlatform(entryPoints, clientExtensions, options.debugContext, attempts);
    }
    if (!egl) {
        if (previous.context != EGL_NO_CONTEXT) {
            eglMakeCurrent(previous.display, previous.draw, previous.read, previous.context);
        }
        std::string message = "no OpenGL 4.5 core context through EGL (platform " +
                              std::string(eglPlatformName(platform)) + "); tried ";
        for (std::size_t i = 0; i < attempts.failures.size(); ++i) {
            message += (i == 0 ? "" : "; ") + attempts.failures[i];
        }
        return Error{message};
    }

    const bool echo = glDebugEchoEnabled(options.echoDebugMessages);
    return std::unique_ptr<HeadlessGlContext>(new HeadlessGlContext(std::move(egl), echo));
}

HeadlessGlContext::HeadlessGlContext(std::unique_ptr<Egl> egl, bool echoDebugMessages)
    : m_egl(std::move(egl)) {
    m_info = queryCurrentGlInfo(m_egl->platform, m_egl->detail);
    m_driverWorkarounds = applyDriverWorkarounds(m_info);
    m_debugLog.setEcho(echoDebugMessages);
    m_debugLog.install();
}

HeadlessGlContext::~HeadlessGlContext() {
    const CurrentEgl previous = CurrentEgl::capture();
    if (eglMakeCurrent(m_egl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, m_egl->context) ==
        EGL_TRUE) {
        m_debugLog.uninstall();  // the driver must not call into a destroyed log
    }
    if (previous.context != EGL_NO_CONTEXT && previous.context != m_egl->context) {
        eglMakeCurrent(previous.display, previous.draw, previous.read, previous.context);
    } else {
        eglMakeCurrent(m_egl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    }
    m_egl.reset();
}

Status HeadlessGlContext::makeCurrent() {
    eglBindAPI(EGL_OPENGL_API);
    if (eglMakeCurrent(m_egl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, m_egl->context) !=
        EGL_TRUE) {
        return Error{"HeadlessGlContext: " + eglFailure("eglMakeCurrent")};
    }
    return {};
}

}  // namespace terrain::gl
