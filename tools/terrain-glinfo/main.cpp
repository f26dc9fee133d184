// terrain-glinfo: creates the headless OpenGL 4.5 context every tool uses and says what
// it got, or exactly why it got nothing. The first thing to run on a new machine.
#include "CommandLine.h"
#include "GlInfoJson.h"

#include "terrain/gl/HeadlessGlContext.h"

#include <fmt/core.h>
#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
    CLI::App app{"Create the headless OpenGL 4.5 core context (EGL) and print what it is."};
    std::string platformName = "auto";
    bool json = false;
    app.add_option("--platform", platformName,
                   "EGL platform: auto (device, then surfaceless), device or surfaceless")
        ->check(CLI::IsMember({"auto", "device", "surfaceless"}));
    app.add_flag("--json", json, "Print a JSON object instead of text");
    if (const auto status = terrain::tools::parseCommandLine(app, argc, argv)) return *status;

    using namespace terrain;
    gl::HeadlessGlOptions options;
    options.platform = gl::parseEglPlatform(platformName).value();
    auto context = gl::HeadlessGlContext::create(options);
    if (!context) {
        fmt::print(stderr, "terrain-glinfo: {}\n", context.error().message);
        return 1;
    }
    const gl::GlInfo& info = context.value()->info();
    if (json) {
        std::puts(nlohmann::json{{"gl", tools::glInfoJson(*context.value())}}.dump(2).c_str());
    } else {
        fmt::print(
            "platform:  {} ({})\nvendor:    {}\nrenderer:  {}\nversion:   {}\nGLSL:      {}\n"
            "max tessellation level: {}\nmax texture size: {}\nmax array layers: {}\n"
            "max anisotropy: {}\n",
            info.platform, info.platformDetail, info.vendor, info.renderer, info.version,
            info.glslVersion, info.maxTessGenLevel, info.maxTextureSize, info.maxArrayTextureLayers,
            info.maxTextureAnisotropy);
    }
    return 0;
}
