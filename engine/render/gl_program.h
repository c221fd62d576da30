// Compiling and linking GLSL programs, with the driver's log in the th::Error, and setting their uniforms.
// Internal to the renderer.
// Thread contract: needs the calling thread's current GL context.
#pragma once

#include <glad/gl.h>

#include <Eigen/Core>

namespace th::render {

// Throws th::Error("shader NAME does not compile: <log on one line>") and deletes what it made.
GLuint linkProgram(const char* vertexSource, const char* fragmentSource, const char* name);

// A vec3 uniform of the program in use.
inline void setVector(GLint location, const Eigen::Vector3f& v) {
  glUniform3f(location, v.x(), v.y(), v.z());
}

}  // namespace th::render
