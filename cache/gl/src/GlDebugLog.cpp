// KHR_debug callback and message store.
#include "terrain/gl/GlDebugLog.h"

#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>

namespace terrain::gl {
namespace {

const char* sourceName(GLenum source) {
    switch (source) {
        case GL_DEBUG_SOURCE_API:
            return "API";
        case GL_DEBUG_SOURCE_WINDOW_SYSTEM:
            return "window system";
        case GL_DEBUG_SOURCE_SHADER_COMPILER:
            return "shader compiler";
        case GL_DEBUG_SOURCE_THIRD_PARTY:
            return "third party";
        case GL_DEBUG_SOURCE_APPLICATION:
            return "application";
        default:
            return "other";
    }
}

const char* typeName(GLenum type) {
    switch (type) {
        case GL_DEBUG_TYPE_ERROR:
            return "error";
        case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR:
            return "deprecated behaviour";
        case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR:
            return "undefined behaviour";
        case GL_DEBUG_TYPE_PORTABILITY:
            return "portability";
        case GL_DEBUG_TYPE_PERFORMANCE:
            return "performance";
        case GL_DEBUG_TYPE_MARKER:
            return "marker";
        case GL_DEBUG_TYPE_PUSH_GROUP:
            return "push group";
        case GL_DEBUG_TYPE_POP_GROUP:
            return "pop group";
        default:
            return "other";
    }
}

const char* severityName(GLenum severity) {
    switch (severity) {
        case GL_DEBUG_SEVERITY_HIGH:
            return "high";
        case GL_DEBUG_SEVERITY_MEDIUM:
            return "medium";
        case GL_DEBUG_SEVERITY_LOW:
            return "low";
        case GL_DEBUG_SEVERITY_NOTIFICATION:
            return "notification";
        default:
            return "unknown";
    }
}

void GLAPIENTRY debugCallback(GLenum source, GLenum type, GLuint id, GLenum severity,
                              GLsizei length, const GLchar* message, const void* userParam) {
    auto* log = static_cast<GlDebugLog*>(const_cast<void*>(userParam));
    const std::string_view text = length >= 0
                                      ? std::string_view(message, static_cast<std::size_t>(length))
                                      : std::string_view(message);
    log->record(source, type, id, severity, text);
}

}  // namespace

std::string GlDebugMessage::describe() const {
    std::string line = std::string("GL ") + typeName(type) + " [" + sourceName(source) + ", " +
                       severityName(severity) + ", id " + std::to_string(id) + "]: " + text;
    while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) {
        line.pop_back();
    }
    return line;
}

void GlDebugLog::install() {
    glEnable(GL_DEBUG_OUTPUT);
    // Synchronous: the callback runs inside the offending call, on the render thread, so
    // a breakpoint there shows the culprit and this log needs no locking.
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(&debugCallback, this);
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
}

void GlDebugLog::uninstall() { glDebugMessageCallback(nullptr, nullptr); }

bool GlDebugLog::isError(GLenum type, GLenum severity) {
    return type == GL_DEBUG_TYPE_ERROR || type == GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR ||
           type == GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR || severity == GL_DEBUG_SEVERITY_HIGH;
}

void GlDebugLog::record(GLenum source, GLenum type, GLuint id, GLenum severity,
                        std::string_view text) {
    GlDebugMessage message{.source = source,
                           .type = type,
                           .severity = severity,
                           .id = id,
                           .text = std::string(text),
                           .error = isError(type, severity)};
    ++m_messageCount;
    if (message.error) {
        ++m_errorCount;
    }
    if (m_echo) {
        std::fprintf(stderr, "%s\n", message.describe().c_str());
    }
    if (m_messages.size() < kMaxStoredMessages) {
        m_messages.push_back(std::move(message));
    }
}

std::vector<GlDebugMessage> GlDebugLog::errors() const {
    std::vector<GlDebugMessage> result;
    for (const GlDebugMessage& message : m_messages) {
        if (message.error) {
            result.push_back(message);
        }
    }
    return result;
}

std::string GlDebugLog::formatErrors() const {
    std::string text;
    for (const GlDebugMessage& message : m_messages) {
        if (message.error) {
            text += message.describe();
            text += '\n';
        }
    }
    if (m_errorCount > 0 && text.empty()) {
        text = std::to_string(m_errorCount) + " GL errors (not stored: message cap reached)\n";
    }
    return text;
}

void GlDebugLog::clear() {
    m_messages.clear();
    m_errorCount = 0;
    m_messageCount = 0;
}

bool glDebugEchoEnabled(GlDebugEcho echo) {
    switch (echo) {
        case GlDebugEcho::On:
            return true;
        case GlDebugEcho::Off:
            return false;
        case GlDebugEcho::FromEnvironment:
            break;
    }
    const char* value = std::getenv("TERRAIN_GL_DEBUG");
    return value != nullptr && std::string_view(value) == "1";
}

}  // namespace terrain::gl
