// ImageryTileSource: where the I/O thread gets an imagery layer's tiles (issue 47): read and
// decoded from the layer's files, or generated, as the virtual planet's colours are (its
// heights are generated where a reader would read them, VirtualPlanetPyramid.h). One source
// per thread, like a PyramidReader.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/pyramid/ImageryTile.h"
#include "terrain/pyramid/PyramidManifest.h"
#include "terrain/remote/RemoteStats.h"

#include <cstdint>
#include <filesystem>
#include <memory>

namespace terrain::io {

class ImageryTileSource {
public:
    virtual ~ImageryTileSource() = default;
    /// Fills `out` with tile `id` (reusing its storage): present with its texels, or not
    /// present (info.present = false, rgba empty) when the layer has no tile there, which is
    /// not an error. Errors name the file (or the layer) and the tile: outside the layer's
    /// levels, a missing, truncated or corrupt file, a checksum mismatch.
    virtual Status readTile(const PatchId& id, ImageryTile& out) = 0;
    /// What the source has done over HTTP since it was opened (opening included): zero for
    /// a layer in a folder or a generated one. Read on the thread that reads the tiles.
    virtual remote::RemoteStats remoteStats() const { return {}; }
    /// The bytes of the tiles' payloads read so far, as stored (compressed) in the layer's
    /// files: zero for a generated layer.
    virtual std::uint64_t storedBytesRead() const { return 0; }
};

/// Opens `layer` of the pyramid at `pyramidDir` (a folder, or the virtual planet's name) for
/// the calling thread. Errors name the layer and why it cannot be read.
Result<std::unique_ptr<ImageryTileSource>> openImageryTiles(const std::filesystem::path& pyramidDir,
                                                            const PyramidManifest& manifest,
                                                            const ManifestImageryLayer& layer);

}  // namespace terrain::io
