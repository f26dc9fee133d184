// sweepOtherMethods: the stability suite's poses flown by every LOD method besides the
// default (LodMethod.h), each held only to what it promises: every method settles, draws
// no crack or hole and no NaN; a method that bounds its error (LodMethodInfo::boundsError)
// stays within ε + kRasterTolerancePx. What a method does not promise is printed, not
// asserted, so a failing case shows in the log as it shows in terrain-bench's report.
#pragma once

#include "AccuracyScenes.h"
#include "terrain/runtime/LodStrategyFactory.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <span>
#include <string>
#include <vector>

namespace terrain::test {

inline void sweepOtherMethods(const std::filesystem::path& pyramid, const std::vector<Pose>& poses,
                              const std::string& scene, int widthPx, int heightPx,
                              std::span<const double> errorsPx) {
    auto probe =
        runtime::AccuracyProbe::create(pyramid, {.widthPx = widthPx, .heightPx = heightPx});
    ASSERT_TRUE(probe) << probe.error().message;
    for (const runtime::LodMethodInfo& method : runtime::lodMethods()) {
        if (method.method == runtime::LodMethod::Yusov2011) continue;  // sweep() flies it
        runtime::TerrainSessionOptions options = roomySessionOptions(errorsPx.front());
        options.method = method.method;
        auto opened = runtime::openLodStrategy(pyramid, options);
        ASSERT_TRUE(opened) << opened.error().message;
        runtime::LodStrategy& strategy = *opened.value();
        int frames = 0, over = 0;
        std::uint64_t cracks = 0, unmeasurable = 0;
        double worstRatio = 0.0;
        for (const Pose& pose : poses) {
            for (const double errorPx : errorsPx) {
                const std::string what = scene + " / " + std::string(method.name) + " / " +
                                         pose.name + " at ε = " + std::to_string(errorPx);
                strategy.setErrorPx(errorPx);
                const SettledMeasure m = measureSettledFrame(strategy, *probe.value(), pose.camera,
                                                             measuredStyle());
                std::cout << "[          ] " << what << ": " << m.triangles << " triangles; "
                          << describe(m.accuracy) << "\n";
                expectStable(what, pose.camera, m,
                             {.measurable = method.boundsError, .noCracks = method.skirts});
                // A method without a bound may lie so far from the truth that the measure
                // cannot project some pixels' error (counted): its picture must still be
                // finite. A method without skirts may show crack pixels (counted).
                if (!method.boundsError) {
                    EXPECT_TRUE(std::isfinite(m.accuracy.image.psnrDb)) << what;
                    unmeasurable += m.accuracy.error.nonFinitePixels;
                }
                if (!method.skirts) cracks += m.accuracy.crackPixels();
                ++frames;
                over += m.accuracy.error.maxPx > errorPx + kRasterTolerancePx ? 1 : 0;
                worstRatio = std::max(worstRatio, m.accuracy.error.maxPx / errorPx);
                if (method.boundsError) {
                    EXPECT_LE(m.accuracy.error.maxPx, errorPx + kRasterTolerancePx)
                        << what << ", " << describe(pose.camera) << ": " << describe(m.accuracy);
                }
            }
        }
        strategy.drain(std::chrono::seconds(10));
        std::cout << "[          ] " << scene << " / " << method.name << ": " << over << " of "
                  << frames << " frames over ε + " << kRasterTolerancePx
                  << " px; largest error / ε " << worstRatio;
        if (!method.skirts) std::cout << "; " << cracks << " crack pixels (no skirts)";
        if (!method.boundsError) std::cout << "; " << unmeasurable << " unmeasurable pixels";
        std::cout << "\n";
        ::testing::Test::RecordProperty(
            scene + "_" + std::string(method.name) + "_frames_over_threshold", over);
    }
}

}  // namespace terrain::test
