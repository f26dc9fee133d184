// Handle<Traits>: the one move-only owner of a GL object name, deleting it on destruction.
// Every GL wrapper holds one, so no GL object is ever leaked or deleted twice.
#pragma once

#include "terrain/gl/ObjectLabel.h"

#include <epoxy/gl.h>

#include <string_view>
#include <utility>

namespace terrain::gl {

/// Owns one GL object name. Traits gives kLabelIdentifier (the glObjectLabel namespace)
/// and destroy(GLuint). Create and destroy on the render thread, with the owning
/// context current: GL names mean nothing outside their context.
template <typename Traits>
class Handle {
public:
    Handle() = default;
    explicit Handle(GLuint id) : m_id(id) {}
    ~Handle() { reset(); }

    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    Handle(Handle&& other) noexcept : m_id(std::exchange(other.m_id, 0)) {}
    Handle& operator=(Handle&& other) noexcept {
        if (this != &other) {
            reset();
            m_id = std::exchange(other.m_id, 0);
        }
        return *this;
    }

    GLuint id() const { return m_id; }
    bool valid() const { return m_id != 0; }
    explicit operator bool() const { return valid(); }

    /// Deletes the object now (if any). Render thread only.
    void reset() {
        if (m_id != 0) {
            Traits::destroy(m_id);
            m_id = 0;
        }
    }

    /// Gives up ownership without deleting; the caller deletes the name.
    [[nodiscard]] GLuint release() { return std::exchange(m_id, 0); }

    void setLabel(std::string_view label) const {
        if (m_id != 0) {
            setObjectLabel(Traits::kLabelIdentifier, m_id, label);
        }
    }

private:
    GLuint m_id = 0;
};

struct BufferTraits {
    static constexpr GLenum kLabelIdentifier = GL_BUFFER;
    static void destroy(GLuint id) { glDeleteBuffers(1, &id); }
};
struct TextureTraits {
    static constexpr GLenum kLabelIdentifier = GL_TEXTURE;
    static void destroy(GLuint id) { glDeleteTextures(1, &id); }
};
struct FramebufferTraits {
    static constexpr GLenum kLabelIdentifier = GL_FRAMEBUFFER;
    static void destroy(GLuint id) { glDeleteFramebuffers(1, &id); }
};
struct QueryTraits {
    static constexpr GLenum kLabelIdentifier = GL_QUERY;
    static void destroy(GLuint id) { glDeleteQueries(1, &id); }
};
struct VertexArrayTraits {
    static constexpr GLenum kLabelIdentifier = GL_VERTEX_ARRAY;
    static void destroy(GLuint id) { glDeleteVertexArrays(1, &id); }
};
struct ShaderTraits {
    static constexpr GLenum kLabelIdentifier = GL_SHADER;
    static void destroy(GLuint id) { glDeleteShader(id); }
};
struct ProgramTraits {
    static constexpr GLenum kLabelIdentifier = GL_PROGRAM;
    static void destroy(GLuint id) { glDeleteProgram(id); }
};

using BufferHandle = Handle<BufferTraits>;
using TextureHandle = Handle<TextureTraits>;
using FramebufferHandle = Handle<FramebufferTraits>;
using QueryHandle = Handle<QueryTraits>;
using VertexArrayHandle = Handle<VertexArrayTraits>;
using ShaderHandle = Handle<ShaderTraits>;
using ProgramHandle = Handle<ProgramTraits>;

}  // namespace terrain::gl
