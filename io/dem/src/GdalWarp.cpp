#include "GdalWarp.h"

#include <fmt/format.h>
#include <gdal_utils.h>

#include <memory>
#include <vector>

namespace terrain::io::detail {
namespace {

// Runs one of GDAL's command-line utilities' library forms on an argument list.
template <typename Options, typename New, typename Free>
std::unique_ptr<Options, Free> utilityOptions(const std::vector<std::string>& args, New make,
                                              Free free) {
    std::vector<char*> argv;
    for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
    argv.push_back(nullptr);
    return std::unique_ptr<Options, Free>(make(argv.data(), nullptr), free);
}

// The one band to warp as a dataset of its own, so the warper reads no other band.
Result<GdalDataset> singleBand(GDALDataset& source, int band, const std::string& path) {
    GdalErrorCapture errors;
    auto options =
        utilityOptions<GDALTranslateOptions>({"-of", "VRT", "-b", std::to_string(band)},
                                             GDALTranslateOptionsNew, &GDALTranslateOptionsFree);
    int usageError = 0;
    GdalDataset vrt(GDALDataset::FromHandle(
        GDALTranslate("", GDALDataset::ToHandle(&source), options.get(), &usageError)));
    if (!vrt)
        return Error{fmt::format("{}: GDAL cannot select band {}: {}", path, band,
                                 errors.message("GDALTranslate failed"))};
    return vrt;
}

}  // namespace

bool isWideSampleType(GDALDataType type) {
    return type == GDT_Float64 || type == GDT_Int32 || type == GDT_UInt32 || type == GDT_Int64 ||
           type == GDT_UInt64;
}

Result<WarpedDataset> warpBilinear(GDALDataset& source, const DemInfo& info, const WarpGrid& grid,
                                   bool wide, const std::string& what) {
    std::vector<std::string> args = {
        // XSCALE/YSCALE 1: bilinear interpolation of the four nearest samples. Left to
        // itself the warper widens its kernel along a rotated grid's axes, smoothing the
        // surface (0.94 m off a plane of 3 m per sample).
        "-of", "VRT", "-r", "bilinear", "-wo", "XSCALE=1", "-wo", "YSCALE=1",
        // Exact transforms: no approximation by the warper's own interpolation.
        "-et", "0", "-ot", wide ? "Float64" : "Float32", "-te", fmt::format("{:.17g}", grid.west),
        fmt::format("{:.17g}", grid.south), fmt::format("{:.17g}", grid.east),
        fmt::format("{:.17g}", grid.north), "-ts", std::to_string(grid.width),
        std::to_string(grid.height), "-dstnodata", "nan"};
    if (!grid.targetCrs.empty()) {
        args.push_back("-t_srs");
        args.push_back(grid.targetCrs);
    }
    if (!grid.sourceCrs.empty()) {
        args.push_back("-s_srs");
        args.push_back(grid.sourceCrs);
    }
    if (info.noDataValue) {
        args.push_back("-srcnodata");
        args.push_back(fmt::format("{:.17g}", *info.noDataValue));
    }
    WarpedDataset result;
    GDALDataset* input = &source;
    if (info.bandCount > 1) {
        Result<GdalDataset> selected = singleBand(source, info.band, info.path);
        if (!selected) return selected.error();
        result.band = std::move(selected).value();
        input = result.band.get();
    }
    GdalErrorCapture errors;
    auto options =
        utilityOptions<GDALWarpAppOptions>(args, GDALWarpAppOptionsNew, &GDALWarpAppOptionsFree);
    if (!options)
        return Error{fmt::format("{}: {}", info.path, errors.message("bad GDAL warp options"))};
    GDALDatasetH sources[] = {GDALDataset::ToHandle(input)};
    int usageError = 0;
    result.warped.reset(
        GDALDataset::FromHandle(GDALWarp("", nullptr, 1, sources, options.get(), &usageError)));
    if (!result.warped)
        return Error{fmt::format("{}: GDAL's warper cannot resample it onto {}: {}", info.path,
                                 what, errors.message("GDALWarp failed"))};
    return result;
}

}  // namespace terrain::io::detail
