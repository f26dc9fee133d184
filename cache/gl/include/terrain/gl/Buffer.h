// Buffer: a GL buffer object with immutable storage (glNamedBufferStorage), DSA only, so
// creating or filling it never changes a binding.
#pragma once

#include "terrain/gl/Handle.h"

#include <cstddef>
#include <span>
#include <string_view>

namespace terrain::gl {

class Buffer {
public:
    Buffer() = default;

    /// Creates sizeBytes of immutable storage with glNamedBufferStorage flags
    /// (e.g. GL_DYNAMIC_STORAGE_BIT to allow upload()); initialData may be null or must
    /// hold sizeBytes. Render thread only.
    static Buffer create(std::size_t sizeBytes, GLbitfield storageFlags,
                         std::string_view label = {}, const void* initialData = nullptr);

    /// Creates a buffer holding a copy of `data`. Render thread only.
    template <typename T>
    static Buffer createFrom(std::span<const T> data, GLbitfield storageFlags,
                             std::string_view label = {}) {
        return create(data.size_bytes(), storageFlags, label, data.data());
    }

    /// Overwrites bytes at offsetBytes; needs GL_DYNAMIC_STORAGE_BIT. Render thread only.
    void upload(std::size_t offsetBytes, std::span<const std::byte> bytes);

    /// Copies bytes at offsetBytes into `out` (waits for the GPU). Render thread only.
    void readBack(std::size_t offsetBytes, std::span<std::byte> out) const;

    GLuint id() const { return m_handle.id(); }
    bool valid() const { return m_handle.valid(); }
    std::size_t sizeBytes() const { return m_sizeBytes; }

private:
    BufferHandle m_handle;
    std::size_t m_sizeBytes = 0;
    GLbitfield m_storageFlags = 0;
};

}  // namespace terrain::gl
