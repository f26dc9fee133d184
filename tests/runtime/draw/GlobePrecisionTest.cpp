// The GPU's globe positions against a double-precision reference: the GLSL globePositionM
// that globe.tese places every vertex with, run by a compute probe on the driver (llvmpipe
// here, any GPU where the suite runs) with the instance records the renderer writes
// (globePatchInstance), at the equator, ±180°, within 1 km of both poles, a cube corner and a
// cube edge, from 1 m to 36,000 km, on patches from a whole face (level 0) to level 20.
// Within 10 km of the camera a vertex must be within 1 cm of the reference; anywhere its
// error seen from the camera must stay under 1e-5 rad (0.01 px at 1080p, 60° field of view).
#include "GlTestFixture.h"
#include "terrain/gl/Buffer.h"
#include "terrain/globe/GlobePatch.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/runtime/ProgramBuilder.h"
#include "terrain/runtime/SurfacePlacement.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <iostream>
#include <random>
#include <span>
#include <string>
#include <vector>

namespace terrain::runtime {
namespace {

struct alignas(16) Probe {
    std::array<float, 4> sampleHeight;
    std::array<std::int32_t, 4> instance;
};

class GlobePrecisionTest : public test::GlTest {};

TEST_F(GlobePrecisionTest, GpuPositionsMatchTheDoubleReference) {
    constexpr int kQuads = 128;
    auto program =
        ProgramBuilder("globe position probe").stage("globe_position_probe.comp").build();
    ASSERT_TRUE(program) << program.error().message;
    struct Place {
        std::string name;
        double latitude, longitude;
    };
    const std::vector<Place> places{{"equator", 0.0, 0.0},
                                    {"antimeridian east", 0.3, 179.9999},
                                    {"antimeridian west", -0.3, -179.9999},
                                    {"1 km from the north pole", 89.991, 37.0},
                                    {"1 km from the south pole", -89.991, -122.0},
                                    {"cube corner", 35.26438968, 45.0},
                                    {"cube edge", 12.0, -45.0}};
    std::mt19937_64 random(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<PatchInstance> instances;
    std::vector<Probe> probes;
    struct Expected {
        glm::dvec3 position;
        std::string where;
    };
    std::vector<Expected> expected;
    for (const Place& place : places) {
        for (const double altitude : {1.0, 100.0, 10e3, 1e6, 20e6, 36e6}) {
            const glm::dvec3 camera =
                globe::Wgs84::toEcef({place.latitude, place.longitude, altitude});
            const glm::dvec3 up = globe::Wgs84::upAt(camera);
            const globe::FacePoint nadir = globe::facePointOf(up);
            for (const int level : {0, 4, 8, 12, 16, 20}) {
                const std::int64_t n = globe::patchesPerFaceSide(level);
                const auto index = [&](double c) {
                    return std::min(static_cast<std::int64_t>(c * static_cast<double>(n)), n - 1);
                };
                const globe::GlobePatchId id{nadir.face, level, index(nadir.s), index(nadir.t)};
                PatchDraw draw;
                draw.id = draw.tileId = io::layoutPatchOf(id);
                const PatchInstance instance = globePatchInstance(draw, camera, up, kQuads);
                const int instanceIndex = static_cast<int>(instances.size());
                instances.push_back(instance);
                const double u0 = instance.placement0[1], v0 = instance.placement0[2];
                const double nearSpan = std::min(1.0, 10e3 / (7.0e6 / static_cast<double>(n)));
                for (int k = 0; k < 200; ++k) {
                    const bool near = k < 150;
                    const double du =
                        near ? (2.0 * unit(random) - 1.0) * nearSpan : unit(random) - u0;
                    const double dv =
                        near ? (2.0 * unit(random) - 1.0) * nearSpan : unit(random) - v0;
                    const float sx = static_cast<float>(std::clamp(u0 + du, 0.0, 1.0) * kQuads);
                    const float sy = static_cast<float>(std::clamp(v0 + dv, 0.0, 1.0) * kQuads);
                    const float h = static_cast<float>(-500.0 + 9500.0 * unit(random));
                    probes.push_back({{sx, sy, h, 0.0f}, {instanceIndex, 0, 0, 0}});
                    const globe::FacePoint p =
                        globe::patchPoint(id, double(sx) / kQuads, double(sy) / kQuads);
                    expected.push_back(
                        {globe::Wgs84::pointAlongNormal(globe::directionOf(p.face, p.s, p.t), h) -
                             camera,
                         place.name + ", " + std::to_string(altitude) + " m, level " +
                             std::to_string(level)});
                }
            }
        }
    }
    gl::Buffer instanceBuffer = gl::Buffer::create(sizeof(PatchInstance) * instances.size(),
                                                   GL_DYNAMIC_STORAGE_BIT, "probe instances");
    instanceBuffer.upload(0, std::as_bytes(std::span(instances)));
    gl::Buffer probeBuffer =
        gl::Buffer::create(sizeof(Probe) * probes.size(), GL_DYNAMIC_STORAGE_BIT, "probes");
    probeBuffer.upload(0, std::as_bytes(std::span(probes)));
    gl::Buffer positions =
        gl::Buffer::create(sizeof(float) * 4 * probes.size(), 0, "probe positions");
    program.value().setUniform("u_patchQuads", kQuads);
    glUseProgram(program.value().id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, instanceBuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, probeBuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, positions.id());
    glDispatchCompute(static_cast<GLuint>((probes.size() + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    for (GLuint binding : {0u, 2u, 3u}) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, 0);
    glUseProgram(0);
    std::vector<std::array<float, 4>> result(probes.size());
    positions.readBack(0, std::as_writable_bytes(std::span(result)));

    double worstNear = 0.0, worstAngle = 0.0;
    for (std::size_t i = 0; i < probes.size(); ++i) {
        const glm::dvec3 gpu(result[i][0], result[i][1], result[i][2]);
        const double error = glm::distance(gpu, expected[i].position);
        const double distance = glm::length(expected[i].position);
        if (distance <= 10e3) {
            ASSERT_LT(error, 0.01) << expected[i].where << ", " << distance << " m away";
            worstNear = std::max(worstNear, error);
        }
        ASSERT_LT(error, 1e-5 * distance + 1e-3)
            << expected[i].where << ", " << distance << " m away";
        if (distance > 1.0) worstAngle = std::max(worstAngle, error / distance);
    }
    std::cout << probes.size() << " GPU positions: within 10 km worst " << worstNear * 1000.0
              << " mm; worst angle anywhere " << worstAngle << " rad\n";
}

}  // namespace
}  // namespace terrain::runtime
