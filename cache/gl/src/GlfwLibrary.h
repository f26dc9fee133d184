// GlfwLibrary: glfwInit while at least one owner exists, glfwTerminate after the last,
// and GLFW's error callback collected so failures can be reported as text.
#pragma once

#include "terrain/base/Result.h"

#include <memory>
#include <string>

namespace terrain::gl::detail {

/// One reference to the initialised GLFW library. Main thread only (a GLFW rule).
class GlfwLibrary {
public:
    /// Initialises GLFW if this is the first reference.
    static Result<std::unique_ptr<GlfwLibrary>> acquire();
    ~GlfwLibrary();
    GlfwLibrary(const GlfwLibrary&) = delete;
    GlfwLibrary& operator=(const GlfwLibrary&) = delete;

    /// GLFW errors reported since the last call, "; "-separated; empties the list.
    static std::string takeErrors();

private:
    GlfwLibrary() = default;
};

}  // namespace terrain::gl::detail
