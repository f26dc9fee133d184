// GlDebugLog: collects GL debug output (KHR_debug) of one context, so errors the driver
// reports are counted and shown instead of lost; GL tests fail on any recorded error.
#pragma once

#include <epoxy/gl.h>

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace terrain::gl {

struct GlDebugMessage {
    GLenum source = GL_NONE;
    GLenum type = GL_NONE;
    GLenum severity = GL_NONE;
    GLuint id = 0;
    std::string text;
    bool error = false;  ///< see GlDebugLog::isError

    /// One line: "GL error [API, high, id 1280]: <driver text>".
    std::string describe() const;
};

/// Owned by its context, which installs it; lives at a fixed address because the driver
/// holds a pointer to it. Render thread only (debug output is synchronous).
class GlDebugLog {
public:
    /// Stored messages are capped so a driver that floods debug output cannot grow memory
    /// without bound; the counts keep going.
    static constexpr std::size_t kMaxStoredMessages = 1024;

    GlDebugLog() = default;
    ~GlDebugLog() = default;
    GlDebugLog(const GlDebugLog&) = delete;
    GlDebugLog& operator=(const GlDebugLog&) = delete;

    /// Enables GL_DEBUG_OUTPUT and GL_DEBUG_OUTPUT_SYNCHRONOUS on the current context and
    /// routes its messages here. Render thread only.
    void install();

    /// Stops routing messages here (the current context must be the installed one).
    void uninstall();

    /// Records one message (called by the driver callback; public for tests).
    void record(GLenum source, GLenum type, GLuint id, GLenum severity, std::string_view text);

    /// Messages since the last clear(), oldest first, at most kMaxStoredMessages.
    const std::vector<GlDebugMessage>& messages() const { return m_messages; }

    /// The stored messages that are errors.
    std::vector<GlDebugMessage> errors() const;

    /// Errors since the last clear(), including ones beyond the storage cap.
    std::size_t errorCount() const { return m_errorCount; }

    /// All messages since the last clear(), including ones beyond the storage cap.
    std::size_t messageCount() const { return m_messageCount; }

    /// The stored errors, one describe() line each.
    std::string formatErrors() const;

    void clear();

    /// Echo every message to stderr as it arrives (contexts turn this on when
    /// TERRAIN_GL_DEBUG=1).
    void setEcho(bool echo) { m_echo = echo; }
    bool echo() const { return m_echo; }

private:
    /// Errors are: type ERROR, UNDEFINED_BEHAVIOR or DEPRECATED_BEHAVIOR, or severity HIGH.
    static bool isError(GLenum type, GLenum severity);

    std::vector<GlDebugMessage> m_messages;
    std::size_t m_errorCount = 0;
    std::size_t m_messageCount = 0;
    bool m_echo = false;
};

/// Whether a context's debug log echoes to stderr.
enum class GlDebugEcho {
    FromEnvironment,  ///< on when TERRAIN_GL_DEBUG=1
    On,
    Off,
};

/// Resolves FromEnvironment against TERRAIN_GL_DEBUG.
bool glDebugEchoEnabled(GlDebugEcho echo);

}  // namespace terrain::gl
