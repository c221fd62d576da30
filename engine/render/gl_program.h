// Compiling and linking GLSL programs, with the driver's log in the th::Error. Internal to the renderer.
// Thread contract: needs the calling thread's current GL context.
#pragma once

#include <glad/gl.h>

namespace th::render {

// Throws th::Error("shader NAME does not compile: <log on one line>") and deletes what it made.
GLuint linkProgram(const char* vertexSource, const char* fragmentSource, const char* name);

}  // namespace th::render
