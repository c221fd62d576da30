#include "gl_program.h"

#include <algorithm>
#include <string>

#include "core/error.h"

namespace th::render {
namespace {

std::string oneLine(const char* log) {
  std::string message(log);
  std::replace(message.begin(), message.end(), '\n', ' ');
  while (!message.empty() && message.back() == ' ') message.pop_back();
  return message;
}

GLuint compileShader(GLenum type, const char* source, const char* name) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok == GL_FALSE) {
    char log[2048] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    throw Error(std::string("shader ") + name + (type == GL_VERTEX_SHADER ? " (vertex)" : " (fragment)") +
                " does not compile: " + oneLine(log));
  }
  return shader;
}

}  // namespace

GLuint linkProgram(const char* vertexSource, const char* fragmentSource, const char* name) {
  const GLuint vs = compileShader(GL_VERTEX_SHADER, vertexSource, name);
  GLuint fs = 0;
  try {
    fs = compileShader(GL_FRAGMENT_SHADER, fragmentSource, name);
  } catch (...) {
    glDeleteShader(vs);
    throw;
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok == GL_FALSE) {
    char log[2048] = {};
    glGetProgramInfoLog(program, sizeof log, nullptr, log);
    glDeleteProgram(program);
    throw Error(std::string("shader program ") + name + " does not link: " + oneLine(log));
  }
  return program;
}

}  // namespace th::render
