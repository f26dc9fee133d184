// Texture: a 2D or 2D-array texture with immutable storage (glTextureStorage2D/3D), DSA
// only. The GPU tile pool keeps tiles as layers of 2D-array textures.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/gl/Handle.h"

#include <cstddef>
#include <span>
#include <string_view>

namespace terrain::gl {

struct TextureDesc {
    GLenum internalFormat = GL_RGBA8;  ///< a sized format: GL_RGBA8, GL_R32F, ...
    int width = 0;
    int height = 0;
    int layers = 1;  ///< 1 for a 2D texture
    int levels = 1;  ///< mip levels
};

/// A box of texels in one mip level: x/y in texels, layer = first array layer.
struct TextureRegion {
    int level = 0;
    int x = 0;
    int y = 0;
    int layer = 0;
    int width = 0;
    int height = 0;
    int layers = 1;
};

class Texture {
public:
    Texture() = default;

    /// GL_TEXTURE_2D. Sizes beyond the context's limits give an Error. Render thread only.
    static Result<Texture> create2D(const TextureDesc& desc, std::string_view label = {});

    /// GL_TEXTURE_2D_ARRAY with desc.layers layers. Render thread only.
    static Result<Texture> create2DArray(const TextureDesc& desc, std::string_view label = {});

    /// Copies tightly packed client pixels (format/type as for glTextureSubImage3D) into
    /// `region`; `pixels` must hold exactly imageSizeBytes(region, format, type).
    /// Pixel-store state and the unpack buffer binding are left as they were.
    /// Render thread only.
    void upload(const TextureRegion& region, GLenum format, GLenum type,
                std::span<const std::byte> pixels);

    /// Reads `region` back (glGetTextureSubImage, waits for the GPU) into `out`, which
    /// must hold exactly imageSizeBytes(region, format, type). Render thread only.
    void readBack(const TextureRegion& region, GLenum format, GLenum type,
                  std::span<std::byte> out) const;

    /// Sets filtering and wrapping (texture object state, not global state).
    /// Render thread only.
    void setSampling(GLenum minFilter, GLenum magFilter, GLenum wrap);
    /// GL_TEXTURE_MAX_LEVEL: the finest `level` … this one are sampled. Render thread only.
    void setMaxLevel(int level);
    /// GL_TEXTURE_MAX_ANISOTROPY; `anisotropy` ≥ 1 and at most gl::maxTextureAnisotropy()
    /// (which is 1 where the context has no anisotropic filtering: then this does nothing).
    /// Render thread only.
    void setMaxAnisotropy(float anisotropy);

    /// The whole of one mip level, all layers.
    TextureRegion wholeLevel(int level = 0) const;

    /// Bytes of a tightly packed image of `region` in format/type.
    static std::size_t imageSizeBytes(const TextureRegion& region, GLenum format, GLenum type);

    GLuint id() const { return m_handle.id(); }
    bool valid() const { return m_handle.valid(); }
    GLenum target() const { return m_target; }
    GLenum internalFormat() const { return m_internalFormat; }
    int width() const { return m_width; }
    int height() const { return m_height; }
    int layers() const { return m_layers; }
    int levels() const { return m_levels; }

private:
    static Result<Texture> create(GLenum target, const TextureDesc& desc, std::string_view label);
    bool contains(const TextureRegion& region) const;

    TextureHandle m_handle;
    GLenum m_target = GL_NONE;
    GLenum m_internalFormat = GL_NONE;
    int m_width = 0;
    int m_height = 0;
    int m_layers = 0;
    int m_levels = 0;
};

}  // namespace terrain::gl
