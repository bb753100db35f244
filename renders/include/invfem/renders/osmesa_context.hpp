#pragma once
// RAII owner of an OSMesa OpenGL core-profile context (GL 4.5 on llvmpipe) and its RGBA
// buffer. Create one and reuse it for many frames: creating a context costs far more than a
// frame. Every GL call must happen while it is current on the calling thread.
#include <cstdint>
#include <string>
#include <vector>

struct osmesa_context;  // OSMesa's handle type (<GL/osmesa.h> calls the pointer OSMesaContext)

namespace invfem::renders {

class OSMesaContext {
 public:
  // Creates a core-profile context (GL >= 3.3) with a width x height RGBA buffer and makes it
  // current. Throws std::runtime_error with a clear message if OSMesa cannot create the
  // context, cannot bind the buffer, or glGetString(GL_VERSION) returns NULL (the classic sign
  // of libGL linked in front of libOSMesa).
  OSMesaContext(int width, int height);
  ~OSMesaContext();
  OSMesaContext(const OSMesaContext&) = delete;
  OSMesaContext& operator=(const OSMesaContext&) = delete;

  // Makes this context current on the calling thread with its buffer.
  void make_current();
  // Reallocates the buffer at a new size (no-op if unchanged) and makes the context current.
  void resize(int width, int height);

  int width() const { return width_; }
  int height() const { return height_; }
  const std::string& gl_version() const { return gl_version_; }
  const std::string& gl_renderer() const { return gl_renderer_; }
  // The context's own RGBA buffer (4 bytes a pixel, row 0 at the BOTTOM).
  const std::vector<std::uint8_t>& buffer() const { return buffer_; }

 private:
  osmesa_context* context_ = nullptr;
  int width_ = 0;
  int height_ = 0;
  std::vector<std::uint8_t> buffer_;
  std::string gl_version_;
  std::string gl_renderer_;
};

}  // namespace invfem::renders
