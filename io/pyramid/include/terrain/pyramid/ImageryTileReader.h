// ImageryTileReader: reads a stored imagery layer's tiles (ImageryLayerWriter.h), one reader
// per thread, keeping a few tile files open. Every damage is an error naming the file and
// the tile: a listed file missing, truncated or corrupt, a payload's CRC-32 mismatch.
#pragma once

#include "terrain/pyramid/ImageryLayerIndex.h"
#include "terrain/pyramid/ImageryTileSource.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>

namespace terrain::io {

class ImageryTileReader final : public ImageryTileSource {
public:
    /// Opens the layer folder `layerDir` (reads layer.json) for tiles of layout levels
    /// coarsestLevel … finestLevel.
    static Result<std::unique_ptr<ImageryTileReader>> open(const std::filesystem::path& layerDir,
                                                           int coarsestLevel, int finestLevel);
    ~ImageryTileReader() override;

    Status readTile(const PatchId& id, ImageryTile& out) override;
    remote::RemoteStats remoteStats() const override;
    std::uint64_t storedBytesRead() const override;

    const ImageryLayerIndex& index() const;
    /// Reads every file the index lists and checks each tile (table, CRC, decode): what
    /// terrain-inspect --verify runs. Counts the tiles checked.
    Status verifyAll(std::int64_t& tilesChecked);

private:
    struct State;
    explicit ImageryTileReader(std::unique_ptr<State> state);
    std::unique_ptr<State> m_state;
};

/// Checks one tile file's bytes (header, table, every payload): the decoder the fuzz target
/// runs. The message says what is wrong, without a file name.
Status checkImageryTileFile(std::span<const std::uint8_t> bytes);

}  // namespace terrain::io
