// Reference-counted GLFW initialisation and error capture.
#include "GlfwLibrary.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstdio>

namespace terrain::gl::detail {
namespace {

// GLFW itself is process-wide state with a main-thread rule, so this count is too.
int g_references = 0;

std::string& pendingErrors() {
    static std::string errors;
    return errors;
}

void errorCallback(int code, const char* description) {
    std::string& errors = pendingErrors();
    if (!errors.empty()) {
        errors += "; ";
    }
    char codeText[16];
    std::snprintf(codeText, sizeof codeText, "0x%05X", static_cast<unsigned>(code));
    errors +=
        std::string(description != nullptr ? description : "unknown error") + " (" + codeText + ")";
}

}  // namespace

Result<std::unique_ptr<GlfwLibrary>> GlfwLibrary::acquire() {
    if (g_references == 0) {
        glfwSetErrorCallback(&errorCallback);
        if (glfwInit() != GLFW_TRUE) {
            const std::string errors = takeErrors();
            return Error{"GLFW: glfwInit failed: " +
                         (errors.empty() ? std::string("no reason given") : errors)};
        }
    }
    ++g_references;
    return std::unique_ptr<GlfwLibrary>(new GlfwLibrary());
}

GlfwLibrary::~GlfwLibrary() {
    if (--g_references == 0) {
        glfwTerminate();
    }
}

std::string GlfwLibrary::takeErrors() {
    std::string errors;
    errors.swap(pendingErrors());
    return errors;
}

}  // namespace terrain::gl::detail
