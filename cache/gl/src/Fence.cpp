// Fence: glFenceSync / glClientWaitSync / glDeleteSync behind one owner.
#include "terrain/gl/Fence.h"

#include "terrain/base/Assert.h"

#include <utility>

namespace terrain::gl {
namespace {

constexpr GLuint64 kWaitTimeoutNs = 1'000'000'000;

}  // namespace

Fence Fence::insert() { return Fence(glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0)); }

Fence::Fence(Fence&& other) noexcept : m_sync(std::exchange(other.m_sync, nullptr)) {}

Fence& Fence::operator=(Fence&& other) noexcept {
    if (this != &other) {
        reset();
        m_sync = std::exchange(other.m_sync, nullptr);
    }
    return *this;
}

bool Fence::signalled() const {
    TERRAIN_ASSERT(valid(), "Fence::signalled on an empty fence");
    const GLenum result = glClientWaitSync(m_sync, 0, 0);
    TERRAIN_ASSERT(result != GL_WAIT_FAILED, "Fence: glClientWaitSync failed");
    return result == GL_ALREADY_SIGNALED || result == GL_CONDITION_SATISFIED;
}

void Fence::wait() const {
    TERRAIN_ASSERT(valid(), "Fence::wait on an empty fence");
    // Flush once, so the fence itself reaches the GPU; then wait as long as it takes.
    GLenum result = glClientWaitSync(m_sync, GL_SYNC_FLUSH_COMMANDS_BIT, kWaitTimeoutNs);
    while (result == GL_TIMEOUT_EXPIRED) result = glClientWaitSync(m_sync, 0, kWaitTimeoutNs);
    TERRAIN_ASSERT(result != GL_WAIT_FAILED, "Fence: glClientWaitSync failed");
}

void Fence::reset() {
    if (m_sync != nullptr) {
        glDeleteSync(m_sync);
        m_sync = nullptr;
    }
}

}  // namespace terrain::gl
