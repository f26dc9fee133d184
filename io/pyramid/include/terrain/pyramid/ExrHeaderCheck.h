// ExrHeaderCheck: the walk over an OpenEXR file's headers that must come before the OpenEXR
// library opens an untrusted file. OpenEXR 3.1 allocates (and fills) whatever a header says
// before it reads it: one changed byte in a 20 KB shard makes it build a 1.2 GB string, or
// a chunk offset table for a data window of 2^31 rows, taking over 10 s and gigabytes
// before it fails (found by fuzz-shard). The walk reads the headers as OpenEXR does
// (magic, version, then per part name\0 type\0 size value, a \0 after each header, one
// more after the last header of a multi-part file; values of the types OpenEXR knows in
// their own layout) and refuses an attribute the file cannot hold, a value that does not
// fill its stated size, and a chunk offset table (chunkCount, or the chunks of the data
// window) larger than the file.
#pragma once

#include "terrain/base/Result.h"

#include <cstdint>
#include <filesystem>
#include <istream>

namespace terrain::io {

/// Ok when every attribute of every header of the OpenEXR file at `path` fits in the file;
/// otherwise an Error saying what is wrong (without the path: callers name the file).
/// Files that are not OpenEXR are an Error too.
Status checkExrHeaderSizes(const std::filesystem::path& path);

/// The same walk over a file of `fileSize` bytes read from `in` (at its start).
Status checkExrHeaderSizes(std::istream& in, std::uintmax_t fileSize);

}  // namespace terrain::io
