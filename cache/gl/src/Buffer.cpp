// Buffer objects through DSA: no binding point is touched.
#include "terrain/gl/Buffer.h"

#include "terrain/base/Assert.h"

namespace terrain::gl {

Buffer Buffer::create(std::size_t sizeBytes, GLbitfield storageFlags, std::string_view label,
                      const void* initialData) {
    TERRAIN_ASSERT(sizeBytes > 0, "a GL buffer needs at least one byte of storage");
    GLuint id = 0;
    glCreateBuffers(1, &id);
    Buffer buffer;
    buffer.m_handle = BufferHandle(id);
    buffer.m_sizeBytes = sizeBytes;
    buffer.m_storageFlags = storageFlags;
    glNamedBufferStorage(id, static_cast<GLsizeiptr>(sizeBytes), initialData, storageFlags);
    buffer.m_handle.setLabel(label);
    return buffer;
}

void Buffer::upload(std::size_t offsetBytes, std::span<const std::byte> bytes) {
    TERRAIN_ASSERT(valid());
    TERRAIN_ASSERT((m_storageFlags & GL_DYNAMIC_STORAGE_BIT) != 0,
                   "Buffer::upload needs GL_DYNAMIC_STORAGE_BIT");
    TERRAIN_ASSERT(offsetBytes <= m_sizeBytes && bytes.size() <= m_sizeBytes - offsetBytes,
                   "Buffer::upload past the end of the buffer");
    if (bytes.empty()) {
        return;
    }
    glNamedBufferSubData(id(), static_cast<GLintptr>(offsetBytes),
                         static_cast<GLsizeiptr>(bytes.size()), bytes.data());
}

void Buffer::readBack(std::size_t offsetBytes, std::span<std::byte> out) const {
    TERRAIN_ASSERT(valid());
    TERRAIN_ASSERT(offsetBytes <= m_sizeBytes && out.size() <= m_sizeBytes - offsetBytes,
                   "Buffer::readBack past the end of the buffer");
    if (out.empty()) {
        return;
    }
    glGetNamedBufferSubData(id(), static_cast<GLintptr>(offsetBytes),
                            static_cast<GLsizeiptr>(out.size()), out.data());
}

}  // namespace terrain::gl
