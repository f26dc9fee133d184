// Fence: a GL sync object (glFenceSync) owned RAII-style: the point in the command stream
// after which the GPU has finished what was submitted before it, e.g. reading an upload's
// bytes from a persistent-mapped buffer the CPU wants to write again.
#pragma once

#include <epoxy/gl.h>

namespace terrain::gl {

/// Move-only; an empty Fence holds no sync object. Render thread only.
class Fence {
public:
    Fence() = default;
    /// A fence after every command submitted so far (GL_SYNC_GPU_COMMANDS_COMPLETE).
    static Fence insert();

    ~Fence() { reset(); }
    Fence(Fence&& other) noexcept;
    Fence& operator=(Fence&& other) noexcept;
    Fence(const Fence&) = delete;
    Fence& operator=(const Fence&) = delete;

    bool valid() const { return m_sync != nullptr; }
    /// Whether the GPU has passed it, without waiting. Must be valid.
    bool signalled() const;
    /// Flushes and blocks until the GPU has passed it. Must be valid.
    void wait() const;
    /// Deletes the sync object (if any).
    void reset();

private:
    explicit Fence(GLsync sync) : m_sync(sync) {}
    GLsync m_sync = nullptr;
};

}  // namespace terrain::gl
