// BenchRecords: summaries by (method, threshold), and the CSV files written atomically, one
// table of columns per file so the header and every row come from the same list.
#include "BenchRecords.h"

#include "terrain/base/AtomicFile.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <utility>

namespace terrain::tools {
namespace {

/// Shortest round-trip form; NaN as an empty field (as the telemetry CSV).
std::string number(double v) { return std::isnan(v) ? std::string() : fmt::format("{}", v); }
std::string number(std::uint64_t v) { return fmt::format("{}", v); }

template <typename Row>
struct Column {
    const char* name;
    std::function<std::string(const Row&)> value;
};

template <typename Row>
Status writeCsv(const std::filesystem::path& path, std::span<const Column<Row>> columns,
                std::span<const Row> rows) {
    return writeAtomically(path, [&](const std::filesystem::path& temporary) -> Status {
        std::FILE* file = std::fopen(temporary.c_str(), "w");
        if (file == nullptr) return Error{path.string() + ": cannot write the file"};
        std::string line;
        for (std::size_t c = 0; c < columns.size(); ++c) {
            line += (c == 0 ? "" : ",") + std::string(columns[c].name);
        }
        line += '\n';
        for (const Row& row : rows) {
            for (std::size_t c = 0; c < columns.size(); ++c) {
                line += (c == 0 ? "" : ",") + columns[c].value(row);
            }
            line += '\n';
        }
        const bool written = std::fwrite(line.data(), 1, line.size(), file) == line.size();
        const bool closed = std::fclose(file) == 0;
        if (!written || !closed) return Error{path.string() + ": write failed (disk full?)"};
        return {};
    });
}

double percentile(std::vector<double> values, double p) {
    std::erase_if(values, [](double v) { return std::isnan(v); });
    if (values.empty()) return kNoValue;
    std::sort(values.begin(), values.end());
    const double rank = p / 100.0 * static_cast<double>(values.size() - 1);
    const auto lo = static_cast<std::size_t>(std::floor(rank));
    const std::size_t hi = std::min(lo + 1, values.size() - 1);
    return values[lo] + (rank - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

double mean(const std::vector<double>& values) {
    double sum = 0.0;
    std::size_t n = 0;
    for (const double v : values) {
        if (std::isnan(v)) continue;
        sum += v;
        ++n;
    }
    return n == 0 ? kNoValue : sum / static_cast<double>(n);
}

double maxOf(const std::vector<double>& values) {
    double best = kNoValue;
    for (const double v : values) {
        if (!std::isnan(v) && (std::isnan(best) || v > best)) best = v;
    }
    return best;
}

double minOf(const std::vector<double>& values) {
    double best = kNoValue;
    for (const double v : values) {
        if (!std::isnan(v) && (std::isnan(best) || v < best)) best = v;
    }
    return best;
}

}  // namespace

std::vector<ThresholdSummary> summarise(std::span<const FrameRecord> records, double tolerancePx) {
    std::vector<std::pair<std::string, double>> keys;
    for (const FrameRecord& r : records) {
        const std::pair<std::string, double> key{r.method, r.thresholdPx};
        if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
    }
    std::vector<ThresholdSummary> out;
    for (const auto& [method, threshold] : keys) {
        ThresholdSummary s;
        s.method = method;
        s.thresholdPx = threshold;
        std::vector<double> triangles, patches, lodUs, gpuMs, drawMs, frameMs, errorMax, errorMean,
            errorP99, fixedMax, rawMax, exactMax, lodErrorMax, rmse, psnr, popping, lodSwitch,
            jumps, shadingSeam, imageryPsnr, imageryTexels, imageryInRange, gpuTexelsP5,
            gpuTexelsP50, gpuTexelsP95, gpuTexelsInRange;
        std::uint64_t horizonCulled = 0, visited = 0;
        for (const FrameRecord& r : records) {
            if (r.method != method || r.thresholdPx != threshold) continue;
            ++s.frames;
            triangles.push_back(static_cast<double>(r.triangles));
            patches.push_back(static_cast<double>(r.patches));
            s.trianglesMax = std::max(s.trianglesMax, r.triangles);
            s.patchesMax = std::max(s.patchesMax, r.patches);
            s.drawCallsMax = std::max(s.drawCallsMax, r.drawCalls);
            s.residentBytesMax = std::max(s.residentBytesMax, r.residentBytes);
            lodUs.push_back(r.lodUpdateUs);
            gpuMs.push_back(r.gpuMs);
            drawMs.push_back(r.drawMs);
            frameMs.push_back(r.frameMs);
            errorMax.push_back(r.errorMaxPx);
            errorMean.push_back(r.errorMeanPx);
            errorP99.push_back(r.errorP99Px);
            fixedMax.push_back(r.errorFixedDiagonalMaxPx);
            rawMax.push_back(r.errorMaxSinglePixelPx);
            exactMax.push_back(r.errorMaxExactPositionPx);
            lodErrorMax.push_back(r.lodErrorMaxPx);
            s.lodFramesOverThreshold += r.lodErrorMaxPx > threshold + tolerancePx ? 1 : 0;
            horizonCulled += r.horizonCulled;
            visited += r.lodVisited;
            rmse.push_back(r.rmse);
            psnr.push_back(r.psnrDb);
            popping.push_back(r.poppingLevels);
            lodSwitch.push_back(r.lodSwitchLevels);
            jumps.push_back(r.lodSwitchJumpShare);
            const bool over = r.errorMaxPx > threshold + tolerancePx || r.nonFinitePixels > 0;
            s.framesOverThreshold += over ? 1 : 0;
            s.nonFinitePixelsTotal += r.nonFinitePixels;
            s.crackPixelsTotal += r.crackPixels;
            s.overdrawnPixelsTotal += r.overdrawnPixels;
            const auto addTo = [](double& total, double value) {
                if (!std::isnan(value)) total = (std::isnan(total) ? 0.0 : total) + value;
            };
            addTo(s.boundaryArtefactPixelsTotal, r.boundaryArtefactPixels);
            addTo(s.boundarySilhouettePixelsTotal, r.boundarySilhouettePixels);
            if (!std::isnan(r.seamSlope)) {
                s.seamSlopeMax = std::isnan(s.seamSlopeMax) ? r.seamSlope
                                                            : std::max(s.seamSlopeMax, r.seamSlope);
                s.framesSeamOverSourceSlope += r.seamSlope > r.seamSourceSlopeP99 ? 1 : 0;
            }
            if (!std::isnan(r.shadingSeamLevels)) shadingSeam.push_back(r.shadingSeamLevels);
            if (!std::isnan(r.imageryPsnrDb)) {
                imageryPsnr.push_back(r.imageryPsnrDb);
                if (std::isnan(s.imageryPsnrDbMin) || r.imageryPsnrDb < s.imageryPsnrDbMin) {
                    s.imageryPsnrDbMin = r.imageryPsnrDb;
                    s.imageryWorstFrame = static_cast<double>(r.frame);
                }
                s.imageryMaxLevels = std::isnan(s.imageryMaxLevels)
                                         ? r.imageryMaxLevels
                                         : std::max(s.imageryMaxLevels, r.imageryMaxLevels);
                addTo(s.imageryVisiblePixelsTotal, r.imageryVisiblePixels);
                addTo(s.imageryUncoveredPixelsTotal, r.imageryUncoveredPixels);
                imageryTexels.push_back(r.imageryTexelsPerPixel);
                imageryInRange.push_back(r.imageryTexelsInRange);
                gpuTexelsP5.push_back(r.imageryGpuTexelsPerPixelP5);
                gpuTexelsP50.push_back(r.imageryGpuTexelsPerPixelP50);
                gpuTexelsP95.push_back(r.imageryGpuTexelsPerPixelP95);
                gpuTexelsInRange.push_back(r.imageryGpuTexelsInRange);
            }
            s.framesWaited += r.waitedForStreaming ? 1 : 0;
            s.framesUnsettled += r.settled ? 0 : 1;
        }
        if (!shadingSeam.empty()) {
            s.shadingSeamLevelsMax = maxOf(shadingSeam);
            s.shadingSeamLevelsMean = mean(shadingSeam);
        }
        s.trianglesMean = mean(triangles);
        s.patchesMean = mean(patches);
        s.lodUpdateUsMean = mean(lodUs);
        s.lodUpdateUsP95 = percentile(lodUs, 95.0);
        s.gpuMsMean = mean(gpuMs);
        s.drawMsMean = mean(drawMs);
        s.frameMsMean = mean(frameMs);
        s.frameMsP95 = percentile(frameMs, 95.0);
        s.errorMaxPx = maxOf(errorMax);
        s.errorMaxMedianPx = percentile(errorMax, 50.0);
        s.errorMeanPx = mean(errorMean);
        s.errorP99MeanPx = mean(errorP99);
        s.errorP99MaxPx = maxOf(errorP99);
        s.errorFixedDiagonalMaxPx = maxOf(fixedMax);
        s.errorMaxSinglePixelPx = maxOf(rawMax);
        s.errorMaxExactPositionPx = maxOf(exactMax);
        s.lodErrorMaxPx = maxOf(lodErrorMax);
        s.horizonCulledFraction =
            visited > 0 ? static_cast<double>(horizonCulled) / static_cast<double>(visited)
                        : kNoValue;
        s.rmseMean = mean(rmse);
        s.psnrDbMean = mean(psnr);
        s.psnrDbMin = minOf(psnr);
        s.poppingLevelsMean = mean(popping);
        if (!imageryPsnr.empty()) {
            s.imageryPsnrDbMean = mean(imageryPsnr);
            s.imageryTexelsPerPixelMedian = percentile(imageryTexels, 50.0);
            s.imageryTexelsInRangeMean = mean(imageryInRange);
            s.imageryGpuTexelsPerPixelP5Median = percentile(gpuTexelsP5, 50.0);
            s.imageryGpuTexelsPerPixelMedian = percentile(gpuTexelsP50, 50.0);
            s.imageryGpuTexelsPerPixelP95Median = percentile(gpuTexelsP95, 50.0);
            s.imageryGpuTexelsInRangeMean = mean(gpuTexelsInRange);
        }
        s.lodSwitchLevelsMean = mean(lodSwitch);
        s.lodSwitchJumpShareMean = mean(jumps);
        out.push_back(s);
    }
    return out;
}

Status writeFramesCsv(const std::filesystem::path& path, std::span<const FrameRecord> records,
                      const std::string& gpuMsSource, bool withPose) {
    using R = FrameRecord;
    std::vector<Column<R>> columns = {
        {"method", [](const R& r) { return r.method; }},
        {"threshold_px", [](const R& r) { return number(r.thresholdPx); }},
        {"frame", [](const R& r) { return number(r.frame); }},
        {"path_time_s", [](const R& r) { return number(r.pathTimeS); }},
        {"camera_x", [](const R& r) { return number(r.cameraPosition.x); }},
        {"camera_y", [](const R& r) { return number(r.cameraPosition.y); }},
        {"camera_z", [](const R& r) { return number(r.cameraPosition.z); }},
        {"camera_yaw_deg", [](const R& r) { return number(r.cameraYawDeg); }},
        {"camera_pitch_deg", [](const R& r) { return number(r.cameraPitchDeg); }},
        {"triangles", [](const R& r) { return number(r.triangles); }},
        {"patches", [](const R& r) { return number(r.patches); }},
        {"patches_culled", [](const R& r) { return number(r.patchesCulled); }},
        {"lod_nodes", [](const R& r) { return number(r.lodNodes); }},
        {"draw_calls", [](const R& r) { return number(r.drawCalls); }},
        {"lod_update_us", [](const R& r) { return number(r.lodUpdateUs); }},
        {"gpu_ms", [](const R& r) { return number(r.gpuMs); }},
        {"gpu_ms_source", [&](const R&) { return gpuMsSource; }},
        {"draw_ms", [](const R& r) { return number(r.drawMs); }},
        {"frame_ms", [](const R& r) { return number(r.frameMs); }},
        {"resident_bytes", [](const R& r) { return number(r.residentBytes); }},
        {"waited_for_streaming",
         [](const R& r) { return std::string(r.waitedForStreaming ? "1" : "0"); }},
        {"settled", [](const R& r) { return std::string(r.settled ? "1" : "0"); }},
        {"error_max_px", [](const R& r) { return number(r.errorMaxPx); }},
        {"error_mean_px", [](const R& r) { return number(r.errorMeanPx); }},
        {"error_p99_px", [](const R& r) { return number(r.errorP99Px); }},
        {"error_pixels", [](const R& r) { return number(r.errorPixels); }},
        {"error_over_threshold_pixels",
         [](const R& r) { return number(r.errorOverThresholdPixels); }},
        {"error_fixed_diagonal_max_px",
         [](const R& r) { return number(r.errorFixedDiagonalMaxPx); }},
        {"error_max_single_pixel_px", [](const R& r) { return number(r.errorMaxSinglePixelPx); }},
        {"error_max_exact_position_px",
         [](const R& r) { return number(r.errorMaxExactPositionPx); }},
        {"error_worst_pixel_x", [](const R& r) { return fmt::format("{}", r.errorWorstX); }},
        {"error_worst_pixel_y", [](const R& r) { return fmt::format("{}", r.errorWorstY); }},
        {"error_worst_world_x", [](const R& r) { return number(r.errorWorstWorld.x); }},
        {"error_worst_world_y", [](const R& r) { return number(r.errorWorstWorld.y); }},
        {"error_worst_world_z", [](const R& r) { return number(r.errorWorstWorld.z); }},
        {"skirt_pixels", [](const R& r) { return number(r.skirtPixels); }},
        {"skirt_error_max_px", [](const R& r) { return number(r.skirtErrorMaxPx); }},
        {"skirt_unbounded_pixels", [](const R& r) { return number(r.skirtUnboundedPixels); }},
        {"non_finite_pixels", [](const R& r) { return number(r.nonFinitePixels); }},
        {"rmse", [](const R& r) { return number(r.rmse); }},
        {"psnr_db", [](const R& r) { return number(r.psnrDb); }},
        {"imagery_psnr_db", [](const R& r) { return number(r.imageryPsnrDb); }},
        {"imagery_max_levels", [](const R& r) { return number(r.imageryMaxLevels); }},
        {"imagery_visible_pixels", [](const R& r) { return number(r.imageryVisiblePixels); }},
        {"imagery_compared_pixels", [](const R& r) { return number(r.imageryComparedPixels); }},
        {"imagery_uncovered_pixels", [](const R& r) { return number(r.imageryUncoveredPixels); }},
        {"imagery_texels_per_pixel", [](const R& r) { return number(r.imageryTexelsPerPixel); }},
        {"imagery_texels_in_range", [](const R& r) { return number(r.imageryTexelsInRange); }},
        {"imagery_gpu_texels_per_pixel_p5",
         [](const R& r) { return number(r.imageryGpuTexelsPerPixelP5); }},
        {"imagery_gpu_texels_per_pixel_p50",
         [](const R& r) { return number(r.imageryGpuTexelsPerPixelP50); }},
        {"imagery_gpu_texels_per_pixel_p95",
         [](const R& r) { return number(r.imageryGpuTexelsPerPixelP95); }},
        {"imagery_gpu_texels_in_range",
         [](const R& r) { return number(r.imageryGpuTexelsInRange); }},
        {"crack_pixels", [](const R& r) { return number(r.crackPixels); }},
        {"uncovered_pixels", [](const R& r) { return number(r.uncoveredPixels); }},
        {"diagonal_uncovered_pixels", [](const R& r) { return number(r.diagonalUncoveredPixels); }},
        {"popping_levels", [](const R& r) { return number(r.poppingLevels); }},
        {"lod_change_levels", [](const R& r) { return number(r.lodChangeLevels); }},
        {"reference_change_levels", [](const R& r) { return number(r.referenceChangeLevels); }},
        {"lod_switch_levels", [](const R& r) { return number(r.lodSwitchLevels); }},
        {"lod_switch_jump_share", [](const R& r) { return number(r.lodSwitchJumpShare); }},
        {"reference_triangles", [](const R& r) { return number(r.referenceTriangles); }},
        {"reference_ms", [](const R& r) { return number(r.referenceMs); }},
        {"camera_height_m", [](const R& r) { return number(r.cameraHeightM); }},
        {"horizon_culled", [](const R& r) { return number(r.horizonCulled); }},
        {"lod_visited", [](const R& r) { return number(r.lodVisited); }},
        {"patches_virtual", [](const R& r) { return number(r.patchesVirtual); }},
        {"patches_bare", [](const R& r) { return number(r.patchesBare); }},
        {"patches_native", [](const R& r) { return number(r.patchesNative); }},
        {"native_windows", [](const R& r) { return number(r.nativeWindows); }},
        {"native_window_depth_max",
         [](const R& r) { return number(std::uint64_t(r.nativeWindowDepthMax)); }},
        {"lod_error_max_px", [](const R& r) { return number(r.lodErrorMaxPx); }},
        {"overdrawn_pixels", [](const R& r) { return number(r.overdrawnPixels); }},
        {"boundary_artefact_pixels", [](const R& r) { return number(r.boundaryArtefactPixels); }},
        {"boundary_silhouette_pixels",
         [](const R& r) { return number(r.boundarySilhouettePixels); }},
        {"seam_slope", [](const R& r) { return number(r.seamSlope); }},
        {"seam_source_slope_p99", [](const R& r) { return number(r.seamSourceSlopeP99); }},
        {"shading_step_boundary_levels",
         [](const R& r) { return number(r.shadingStepBoundaryLevels); }},
        {"shading_step_interior_levels",
         [](const R& r) { return number(r.shadingStepInteriorLevels); }},
        {"shading_seam_levels", [](const R& r) { return number(r.shadingSeamLevels); }},
    };
    if (withPose) columns.insert(columns.begin() + 2, {"pose", [](const R& r) { return r.pose; }});
    return writeCsv<R>(path, columns, records);
}

Status writeSummaryCsv(const std::filesystem::path& path,
                       std::span<const ThresholdSummary> summaries,
                       const std::string& gpuMsSource) {
    using S = ThresholdSummary;
    const std::vector<Column<S>> columns = {
        {"method", [](const S& s) { return s.method; }},
        {"threshold_px", [](const S& s) { return number(s.thresholdPx); }},
        {"frames", [](const S& s) { return number(s.frames); }},
        {"triangles_mean", [](const S& s) { return number(s.trianglesMean); }},
        {"triangles_max", [](const S& s) { return number(s.trianglesMax); }},
        {"patches_mean", [](const S& s) { return number(s.patchesMean); }},
        {"draw_calls_max", [](const S& s) { return number(s.drawCallsMax); }},
        {"lod_update_us_mean", [](const S& s) { return number(s.lodUpdateUsMean); }},
        {"lod_update_us_p95", [](const S& s) { return number(s.lodUpdateUsP95); }},
        {"gpu_ms_mean", [](const S& s) { return number(s.gpuMsMean); }},
        {"gpu_ms_source", [&](const S&) { return gpuMsSource; }},
        {"draw_ms_mean", [](const S& s) { return number(s.drawMsMean); }},
        {"frame_ms_mean", [](const S& s) { return number(s.frameMsMean); }},
        {"frame_ms_p95", [](const S& s) { return number(s.frameMsP95); }},
        {"resident_bytes_max", [](const S& s) { return number(s.residentBytesMax); }},
        {"error_max_px", [](const S& s) { return number(s.errorMaxPx); }},
        {"error_max_median_px", [](const S& s) { return number(s.errorMaxMedianPx); }},
        {"error_mean_px", [](const S& s) { return number(s.errorMeanPx); }},
        {"error_p99_mean_px", [](const S& s) { return number(s.errorP99MeanPx); }},
        {"frames_over_threshold", [](const S& s) { return number(s.framesOverThreshold); }},
        {"non_finite_pixels_total", [](const S& s) { return number(s.nonFinitePixelsTotal); }},
        {"error_fixed_diagonal_max_px",
         [](const S& s) { return number(s.errorFixedDiagonalMaxPx); }},
        {"error_max_single_pixel_px", [](const S& s) { return number(s.errorMaxSinglePixelPx); }},
        {"error_max_exact_position_px",
         [](const S& s) { return number(s.errorMaxExactPositionPx); }},
        {"rmse_mean", [](const S& s) { return number(s.rmseMean); }},
        {"psnr_db_mean", [](const S& s) { return number(s.psnrDbMean); }},
        {"psnr_db_min", [](const S& s) { return number(s.psnrDbMin); }},
        {"imagery_psnr_db_mean", [](const S& s) { return number(s.imageryPsnrDbMean); }},
        {"imagery_psnr_db_min", [](const S& s) { return number(s.imageryPsnrDbMin); }},
        {"imagery_worst_frame", [](const S& s) { return number(s.imageryWorstFrame); }},
        {"imagery_max_levels", [](const S& s) { return number(s.imageryMaxLevels); }},
        {"imagery_visible_pixels_total",
         [](const S& s) { return number(s.imageryVisiblePixelsTotal); }},
        {"imagery_uncovered_pixels_total",
         [](const S& s) { return number(s.imageryUncoveredPixelsTotal); }},
        {"imagery_texels_per_pixel_median",
         [](const S& s) { return number(s.imageryTexelsPerPixelMedian); }},
        {"imagery_texels_in_range_mean",
         [](const S& s) { return number(s.imageryTexelsInRangeMean); }},
        {"imagery_gpu_texels_per_pixel_p5_median",
         [](const S& s) { return number(s.imageryGpuTexelsPerPixelP5Median); }},
        {"imagery_gpu_texels_per_pixel_median",
         [](const S& s) { return number(s.imageryGpuTexelsPerPixelMedian); }},
        {"imagery_gpu_texels_per_pixel_p95_median",
         [](const S& s) { return number(s.imageryGpuTexelsPerPixelP95Median); }},
        {"imagery_gpu_texels_in_range_mean",
         [](const S& s) { return number(s.imageryGpuTexelsInRangeMean); }},
        {"crack_pixels_total", [](const S& s) { return number(s.crackPixelsTotal); }},
        {"popping_levels_mean", [](const S& s) { return number(s.poppingLevelsMean); }},
        {"lod_switch_levels_mean", [](const S& s) { return number(s.lodSwitchLevelsMean); }},
        {"lod_switch_jump_share_mean", [](const S& s) { return number(s.lodSwitchJumpShareMean); }},
        {"frames_waited", [](const S& s) { return number(s.framesWaited); }},
        {"frames_unsettled", [](const S& s) { return number(s.framesUnsettled); }},
        {"patches_max", [](const S& s) { return number(s.patchesMax); }},
        {"error_p99_max_px", [](const S& s) { return number(s.errorP99MaxPx); }},
        {"lod_error_max_px", [](const S& s) { return number(s.lodErrorMaxPx); }},
        {"lod_frames_over_threshold", [](const S& s) { return number(s.lodFramesOverThreshold); }},
        {"horizon_culled_fraction", [](const S& s) { return number(s.horizonCulledFraction); }},
        {"overdrawn_pixels_total", [](const S& s) { return number(s.overdrawnPixelsTotal); }},
        {"boundary_artefact_pixels_total",
         [](const S& s) { return number(s.boundaryArtefactPixelsTotal); }},
        {"boundary_silhouette_pixels_total",
         [](const S& s) { return number(s.boundarySilhouettePixelsTotal); }},
        {"seam_slope_max", [](const S& s) { return number(s.seamSlopeMax); }},
        {"frames_seam_over_source_slope",
         [](const S& s) { return number(s.framesSeamOverSourceSlope); }},
        {"shading_seam_levels_max", [](const S& s) { return number(s.shadingSeamLevelsMax); }},
        {"shading_seam_levels_mean", [](const S& s) { return number(s.shadingSeamLevelsMean); }},
    };
    return writeCsv<S>(path, columns, summaries);
}

}  // namespace terrain::tools
