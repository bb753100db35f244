#pragma once
// Private: GLSL program building for the renderer. Needs a current GL context.
#include <GL/osmesa.h>

#include <string>

namespace invfem::renders::detail {

// Compiles and links a vertex + fragment shader pair; throws std::runtime_error with the
// program name and the driver's info log on failure.
GLuint build_program(const char* vertex_source, const char* fragment_source, const std::string& name);

// Throws std::runtime_error naming `where` if glGetError reports an error.
void check_gl(const std::string& where);

}  // namespace invfem::renders::detail
