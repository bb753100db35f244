#include "gl_program.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <vector>

namespace invfem::renders::detail {
namespace {

std::string shader_log(GLuint shader) {
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::vector<char> log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  glGetShaderInfoLog(shader, length, nullptr, log.data());
  return log.data();
}

GLuint compile(GLenum stage, const char* source, const std::string& name) {
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = shader_log(shader);
    glDeleteShader(shader);
    throw std::runtime_error("renderer: " + name + (stage == GL_VERTEX_SHADER ? " vertex" : " fragment") +
                             " shader failed to compile: " + log);
  }
  return shader;
}

}  // namespace

GLuint build_program(const char* vertex_source, const char* fragment_source, const std::string& name) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex_source, name);
  GLuint fs = 0;
  try {
    fs = compile(GL_FRAGMENT_SHADER, fragment_source, name);
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
  if (!ok) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program, length, nullptr, log.data());
    glDeleteProgram(program);
    throw std::runtime_error("renderer: " + name + " program failed to link: " + std::string(log.data()));
  }
  return program;
}

void check_gl(const std::string& where) {
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR) {
    // Drain any further queued errors so the next check starts clean.
    while (glGetError() != GL_NO_ERROR) {
    }
    throw std::runtime_error("renderer: OpenGL error 0x" + [&] {
      char buf[16];
      std::snprintf(buf, sizeof buf, "%04X", error);
      return std::string(buf);
    }() + " during " + where);
  }
}

}  // namespace invfem::renders::detail
