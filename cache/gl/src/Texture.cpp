// 2D and 2D-array textures: limits checked up front so a bad configuration (too many
// pool layers, a huge tile) is an Error at creation, not a GL error later.
#include "terrain/gl/Texture.h"

#include "terrain/base/Assert.h"
#include "terrain/gl/PixelStoreScope.h"

#include <algorithm>
#include <bit>
#include <cstdio>
#include <string>

namespace terrain::gl {
namespace {

int getInteger(GLenum name) {
    GLint value = 0;
    glGetIntegerv(name, &value);
    return value;
}

std::string describe(std::string_view label) {
    return label.empty() ? std::string("texture") : "texture '" + std::string(label) + "'";
}

std::string hexEnum(GLenum value) {
    char text[16];
    std::snprintf(text, sizeof text, "0x%04X", value);
    return text;
}

std::size_t componentCount(GLenum format) {
    switch (format) {
        case GL_RED:
        case GL_GREEN:
        case GL_BLUE:
        case GL_RED_INTEGER:
        case GL_DEPTH_COMPONENT:
        case GL_STENCIL_INDEX:
            return 1;
        case GL_RG:
        case GL_RG_INTEGER:
        case GL_DEPTH_STENCIL:
            return 2;
        case GL_RGB:
        case GL_BGR:
        case GL_RGB_INTEGER:
        case GL_BGR_INTEGER:
            return 3;
        case GL_RGBA:
        case GL_BGRA:
        case GL_RGBA_INTEGER:
        case GL_BGRA_INTEGER:
            return 4;
        default:
            return 0;
    }
}

/// Bytes per pixel of format/type, 0 when the combination is not one this table knows.
std::size_t pixelSizeBytes(GLenum format, GLenum type) {
    switch (type) {
        // Packed types hold a whole pixel whatever the component count.
        case GL_UNSIGNED_BYTE_3_3_2:
        case GL_UNSIGNED_BYTE_2_3_3_REV:
            return 1;
        case GL_UNSIGNED_SHORT_5_6_5:
        case GL_UNSIGNED_SHORT_5_6_5_REV:
        case GL_UNSIGNED_SHORT_4_4_4_4:
        case GL_UNSIGNED_SHORT_4_4_4_4_REV:
        case GL_UNSIGNED_SHORT_5_5_5_1:
        case GL_UNSIGNED_SHORT_1_5_5_5_REV:
            return 2;
        case GL_UNSIGNED_INT_8_8_8_8:
        case GL_UNSIGNED_INT_8_8_8_8_REV:
        case GL_UNSIGNED_INT_10_10_10_2:
        case GL_UNSIGNED_INT_2_10_10_10_REV:
        case GL_UNSIGNED_INT_24_8:
        case GL_UNSIGNED_INT_10F_11F_11F_REV:
        case GL_UNSIGNED_INT_5_9_9_9_REV:
            return 4;
        case GL_FLOAT_32_UNSIGNED_INT_24_8_REV:
            return 8;
        default:
            break;
    }
    const std::size_t components = componentCount(format);
    switch (type) {
        case GL_UNSIGNED_BYTE:
        case GL_BYTE:
            return components;
        case GL_UNSIGNED_SHORT:
        case GL_SHORT:
        case GL_HALF_FLOAT:
            return components * 2;
        case GL_UNSIGNED_INT:
        case GL_INT:
        case GL_FLOAT:
            return components * 4;
        default:
            return 0;
    }
}

}  // namespace

Result<Texture> Texture::create2D(const TextureDesc& desc, std::string_view label) {
    if (desc.layers != 1) {
        return Error{describe(label) + ": a 2D texture has exactly one layer, not " +
                     std::to_string(desc.layers)};
    }
    return create(GL_TEXTURE_2D, desc, label);
}

Result<Texture> Texture::create2DArray(const TextureDesc& desc, std::string_view label) {
    return create(GL_TEXTURE_2D_ARRAY, desc, label);
}

Result<Texture> Texture::create(GLenum target, const TextureDesc& desc, std::string_view label) {
    const std::string name = describe(label);
    const int maxSize = getInteger(GL_MAX_TEXTURE_SIZE);
    if (desc.width < 1 || desc.height < 1 || desc.width > maxSize || desc.height > maxSize) {
        return Error{name + ": size " + std::to_string(desc.width) + "x" +
                     std::to_string(desc.height) + " is outside 1.." + std::to_string(maxSize) +
                     " (GL_MAX_TEXTURE_SIZE)"};
    }
    if (target == GL_TEXTURE_2D_ARRAY) {
        const int maxLayers = getInteger(GL_MAX_ARRAY_TEXTURE_LAYERS);
        if (desc.layers < 1 || desc.layers > maxLayers) {
            return Error{name + ": " + std::to_string(desc.layers) + " layers is outside 1.." +
                         std::to_string(maxLayers) + " (GL_MAX_ARRAY_TEXTURE_LAYERS)"};
        }
    }
    const auto largest = static_cast<unsigned>(std::max(desc.width, desc.height));
    const int maxLevels = std::bit_width(largest);
    if (desc.levels < 1 || desc.levels > maxLevels) {
        return Error{name + ": " + std::to_string(desc.levels) + " mip levels is outside 1.." +
                     std::to_string(maxLevels) + " for its size"};
    }

    GLuint id = 0;
    glCreateTextures(target, 1, &id);
    Texture texture;
    texture.m_handle = TextureHandle(id);
    texture.m_target = target;
    texture.m_internalFormat = desc.internalFormat;
    texture.m_width = desc.width;
    texture.m_height = desc.height;
    texture.m_layers = desc.layers;
    texture.m_levels = desc.levels;
    if (target == GL_TEXTURE_2D_ARRAY) {
        glTextureStorage3D(id, desc.levels, desc.internalFormat, desc.width, desc.height,
                           desc.layers);
    } else {
        glTextureStorage2D(id, desc.levels, desc.internalFormat, desc.width, desc.height);
    }
    // Storage failing (out of memory, an unsized format) is the one GL error here that
    // data can cause, so it becomes an Error instead of a half-made texture.
    GLint immutable = GL_FALSE;
    glGetTextureParameteriv(id, GL_TEXTURE_IMMUTABLE_FORMAT, &immutable);
    if (immutable != GL_TRUE) {
        return Error{name + ": glTextureStorage failed for internal format " +
                     hexEnum(desc.internalFormat) + " (unsized format or out of memory)"};
    }
    texture.setSampling(desc.levels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR, GL_LINEAR,
                        GL_CLAMP_TO_EDGE);
    texture.m_handle.setLabel(label);
    return texture;
}

void Texture::setSampling(GLenum minFilter, GLenum magFilter, GLenum wrap) {
    TERRAIN_ASSERT(valid());
    glTextureParameteri(id(), GL_TEXTURE_MIN_FILTER, static_cast<GLint>(minFilter));
    glTextureParameteri(id(), GL_TEXTURE_MAG_FILTER, static_cast<GLint>(magFilter));
    glTextureParameteri(id(), GL_TEXTURE_WRAP_S, static_cast<GLint>(wrap));
    glTextureParameteri(id(), GL_TEXTURE_WRAP_T, static_cast<GLint>(wrap));
}

void Texture::setMaxLevel(int level) {
    TERRAIN_ASSERT(valid() && level >= 0 && level < m_levels);
    glTextureParameteri(id(), GL_TEXTURE_MAX_LEVEL, level);
}

void Texture::setMaxAnisotropy(float anisotropy) {
    TERRAIN_ASSERT(valid() && anisotropy >= 1.0f);
    if (anisotropy <= 1.0f) return;  // the default; the context may not know the parameter
    glTextureParameterf(id(), GL_TEXTURE_MAX_ANISOTROPY, anisotropy);
}

TextureRegion Texture::wholeLevel(int level) const {
    TERRAIN_ASSERT(level >= 0 && level < m_levels);
    return TextureRegion{.level = level,
                         .x = 0,
                         .y = 0,
                         .layer = 0,
                         .width = std::max(1, m_width >> level),
                         .height = std::max(1, m_height >> level),
                         .layers = m_layers};
}

std::size_t Texture::imageSizeBytes(const TextureRegion& region, GLenum format, GLenum type) {
    const std::size_t pixelBytes = pixelSizeBytes(format, type);
    TERRAIN_ASSERT(pixelBytes > 0, "Texture: unknown pixel format/type combination");
    return pixelBytes * static_cast<std::size_t>(region.width) *
           static_cast<std::size_t>(region.height) * static_cast<std::size_t>(region.layers);
}

bool Texture::contains(const TextureRegion& region) const {
    if (region.level < 0 || region.level >= m_levels) {
        return false;
    }
    const TextureRegion level = wholeLevel(region.level);
    return region.x >= 0 && region.y >= 0 && region.layer >= 0 && region.width >= 0 &&
           region.height >= 0 && region.layers >= 0 && region.x + region.width <= level.width &&
           region.y + region.height <= level.height && region.layer + region.layers <= level.layers;
}

void Texture::upload(const TextureRegion& region, GLenum format, GLenum type,
                     std::span<const std::byte> pixels) {
    TERRAIN_ASSERT(valid());
    TERRAIN_ASSERT(contains(region), "Texture::upload outside the texture");
    TERRAIN_ASSERT(pixels.size() == imageSizeBytes(region, format, type),
                   "Texture::upload: pixel span does not match the region");
    const PixelStoreScope pixelStore;
    if (m_target == GL_TEXTURE_2D_ARRAY) {
        glTextureSubImage3D(id(), region.level, region.x, region.y, region.layer, region.width,
                            region.height, region.layers, format, type, pixels.data());
    } else {
        glTextureSubImage2D(id(), region.level, region.x, region.y, region.width, region.height,
                            format, type, pixels.data());
    }
}

void Texture::readBack(const TextureRegion& region, GLenum format, GLenum type,
                       std::span<std::byte> out) const {
    TERRAIN_ASSERT(valid());
    TERRAIN_ASSERT(contains(region), "Texture::readBack outside the texture");
    TERRAIN_ASSERT(out.size() == imageSizeBytes(region, format, type),
                   "Texture::readBack: output span does not match the region");
    const PixelStoreScope pixelStore;
    glGetTextureSubImage(id(), region.level, region.x, region.y, region.layer, region.width,
                         region.height, region.layers, format, type,
                         static_cast<GLsizei>(out.size()), out.data());
}

}  // namespace terrain::gl
