// openLodStrategy: the method → strategy table.
#include "terrain/runtime/LodStrategyFactory.h"

#include "terrain/runtime/GeometrySplittingStrategy.h"
#include "terrain/runtime/RipollesStrategy.h"
#include "terrain/runtime/RtinStrategy.h"

namespace terrain::runtime {

Result<std::unique_ptr<LodStrategy>> openLodStrategy(const std::filesystem::path& pyramid,
                                                     const TerrainSessionOptions& options) {
    const auto named = [&](const Error& e) {
        return Error{std::string(lodMethodName(options.method)) + ": " + e.message};
    };
    switch (options.method) {
        case LodMethod::Yusov2011:
        case LodMethod::ChunkedLod:
        case LodMethod::Uniform:
        case LodMethod::Livny2007:
        case LodMethod::Cdlod:
        case LodMethod::Valdetaro2011: {
            auto session = TerrainSession::open(pyramid, options);
            if (!session) return named(session.error());
            return std::unique_ptr<LodStrategy>(std::move(session).value());
        }
        case LodMethod::Lee2011: {
            auto lee = GeometrySplittingStrategy::open(pyramid, options.lod.errorPx);
            if (!lee) return named(lee.error());
            return std::unique_ptr<LodStrategy>(std::move(lee).value());
        }
        case LodMethod::Ripolles: {
            auto ripolles = RipollesStrategy::open(pyramid, options.lod.errorPx, options.ripolles);
            if (!ripolles) return named(ripolles.error());
            return std::unique_ptr<LodStrategy>(std::move(ripolles).value());
        }
        case LodMethod::Rtin: {
            auto rtin = RtinStrategy::open(pyramid, options.lod.errorPx);
            if (!rtin) return named(rtin.error());
            return std::unique_ptr<LodStrategy>(std::move(rtin).value());
        }
    }
    return Error{"unknown LOD method"};
}

}  // namespace terrain::runtime
