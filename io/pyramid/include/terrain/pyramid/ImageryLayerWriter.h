// ImageryLayerWriter: writes an imagery layer's tiles into its folder (docs/imagery.md,
// "Tile files"): 16 × 16 tiles per file, L<level>/<gy>/<gx>.tiles, each tile a WebP payload
// with its CRC-32, and layer.json listing the files. Everything goes into a temporary folder
// beside the layer's; finish() renames it into place, and a writer destroyed unfinished
// removes it: no reader ever sees half a layer.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/ImageryLayerIndex.h"
#include "terrain/pyramid/ImageryTile.h"

#include <filesystem>
#include <memory>

namespace terrain::io {

struct ImageryEncoding {
    /// WebP lossless (every texel exact) instead of lossy.
    bool lossless = false;
    /// Lossy WebP quality, 0 … 100 (alpha is always kept losslessly).
    int quality = 85;
};

class ImageryLayerWriter {
public:
    /// Reserves `<parent>/.<name>.tmp-<pid>` for layer folder `layerDir` (its parent must
    /// exist or be creatable). Fails naming the folder.
    static Result<ImageryLayerWriter> create(const std::filesystem::path& layerDir,
                                             const ImageryEncoding& encoding);

    ImageryLayerWriter(ImageryLayerWriter&&) noexcept;
    ImageryLayerWriter& operator=(ImageryLayerWriter&&) noexcept;
    ~ImageryLayerWriter();  ///< unfinished: removes the temporary folder

    /// Encodes and stores `tile` (present or not: an absent tile writes nothing). Tiles may
    /// come in any order, each once; any thread, concurrently (encoding runs outside the
    /// writer's lock). A fully transparent tile stores no payload.
    Status writeTile(const ImageryTile& tile);

    /// A tile written before, decoded as a reader would decode it (lossy WebP's texels, not
    /// the ones given to writeTile): the imagery builder makes a coarser level from the
    /// finer one's stored texels. A tile not written comes back not present; a transparent
    /// one (no payload) as zeros. Any thread, concurrently with other reads; not after
    /// finish. Fails naming the file and the tile.
    Status readBack(const PatchId& id, ImageryTile& out) const;

    /// Writes every file's table and layer.json, then renames the folder to layerDir;
    /// an existing layerDir is replaced when `replaceExisting`, else an error. Call once.
    Status finish(bool replaceExisting);

    const std::filesystem::path& layerDir() const;
    /// What was written so far (after finish: what the layer holds).
    const ImageryLayerIndex& index() const;

private:
    struct State;
    explicit ImageryLayerWriter(std::unique_ptr<State> state);
    std::unique_ptr<State> m_state;
};

}  // namespace terrain::io
