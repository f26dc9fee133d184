// An application that embeds the installed runtime: evaluates the procedural terrain,
// opens a headless OpenGL 4.5 context and builds an embedded shader program.
#include <terrain/gl/HeadlessGlContext.h>
#include <terrain/source/ProceduralTerrain.h>
#include <terrain/runtime/ProgramBuilder.h>

#include <cmath>
#include <cstdio>

int main() {
    using namespace terrain;
    auto terrain = io::ProceduralTerrain::create({});
    if (!terrain) {
        std::fprintf(stderr, "consumer: %s\n", terrain.error().message.c_str());
        return 1;
    }
    const float h = terrain.value().sample(512, 512);
    if (!std::isfinite(h)) return 1;

    auto context = gl::HeadlessGlContext::create();
    if (!context) {
        std::fprintf(stderr, "consumer: %s\n", context.error().message.c_str());
        return 1;
    }
    auto program = runtime::ProgramBuilder("consumer")
                       .stage("terrain.vert")
                       .stage("terrain.tesc")
                       .stage("terrain.tese")
                       .stage("terrain.frag")
                       .build();
    if (!program) {
        std::fprintf(stderr, "consumer: %s\n", program.error().message.c_str());
        return 1;
    }
    std::printf("consumer: height %.2f m, %s, program built\n", h,
                context.value()->info().renderer.c_str());
    return 0;
}
