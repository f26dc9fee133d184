// ExrHeaderCheck: the walk over an OpenEXR file's headers that must come before the OpenEXR
// library opens an untrusted file. OpenEXR 3.1 allocates (and fills) whatever an attribute's
// size field says before reading it: one flipped byte in a 20 KB shard makes it build a
// 2 GB string, 10 s and 2 GB of memory before it fails (found by fuzz-shard). The walk reads
// only the attributes' names, types and sizes (OpenEXR file layout: magic, version, then
// per part name\0 type\0 size value, a \0 after each header, one more after the last
// header of a multi-part file) and refuses a size the file cannot hold.
#pragma once

#include "terrain/base/Result.h"

#include <filesystem>

namespace terrain::io {

/// Ok when every attribute of every header of the OpenEXR file at `path` fits in the file;
/// otherwise an Error saying what is wrong (without the path: callers name the file).
/// Files that are not OpenEXR are an Error too.
Status checkExrHeaderSizes(const std::filesystem::path& path);

}  // namespace terrain::io
