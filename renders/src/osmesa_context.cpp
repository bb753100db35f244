#include "invfem/renders/osmesa_context.hpp"

#include <GL/osmesa.h>

#include <stdexcept>

namespace invfem::renders {
namespace {

void check_size(int width, int height) {
  // 16384 is llvmpipe's largest framebuffer side.
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw std::invalid_argument("OSMesaContext: buffer size " + std::to_string(width) + "x" +
                                std::to_string(height) + " is outside 1..16384");
}

}  // namespace

OSMesaContext::OSMesaContext(int width, int height) {
  check_size(width, height);
  // Core profile 3.3 asked for; llvmpipe answers with 4.5 core. The default framebuffer gets a
  // depth buffer too, though the renderer draws into its own FBOs.
  const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                         OSMESA_PROFILE, OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 3,
                         OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
  context_ = OSMesaCreateContextAttribs(attribs, nullptr);
  if (!context_)
    throw std::runtime_error(
        "OSMesaContext: OSMesaCreateContextAttribs failed to create an OpenGL 3.3 core-profile "
        "context (is libosmesa6 from Mesa >= 20 installed, with llvmpipe?)");
  try {
    resize(width, height);
    const GLubyte* version = glGetString(GL_VERSION);
    if (!version)
      throw std::runtime_error(
          "OSMesaContext: glGetString(GL_VERSION) returned NULL after OSMesaMakeCurrent; GL calls "
          "are not reaching OSMesa (is libGL linked before libOSMesa?)");
    gl_version_ = reinterpret_cast<const char*>(version);
    const GLubyte* renderer = glGetString(GL_RENDERER);
    gl_renderer_ = renderer ? reinterpret_cast<const char*>(renderer) : "unknown";
  } catch (...) {
    OSMesaDestroyContext(context_);
    context_ = nullptr;
    throw;
  }
}

OSMesaContext::~OSMesaContext() {
  if (context_) OSMesaDestroyContext(context_);
}

void OSMesaContext::make_current() {
  if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, width_, height_))
    throw std::runtime_error("OSMesaContext: OSMesaMakeCurrent failed for a " + std::to_string(width_) +
                             "x" + std::to_string(height_) + " buffer");
}

void OSMesaContext::resize(int width, int height) {
  check_size(width, height);
  if (width != width_ || height != height_ || buffer_.empty()) {
    width_ = width;
    height_ = height;
    buffer_.assign(4 * static_cast<std::size_t>(width) * height, 0);
  }
  make_current();
}

}  // namespace invfem::renders
