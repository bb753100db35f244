#include "invfem/renders/mesh_renderer.hpp"

#include <GL/osmesa.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "gl_program.hpp"
#include "invfem/renders/bitmap_font.hpp"
#include "scene_shaders.hpp"
#include "vertex_stream.hpp"

namespace invfem::renders {

using detail::check_gl;

Eigen::AlignedBox3d mesh_bounds(const std::vector<Drawable>& meshes) {
  Eigen::AlignedBox3d box;  // starts empty
  for (const Drawable& mesh : meshes)
    for (Eigen::Index v = 0; v < mesh.surface.x.rows(); ++v)
      box.extend(Vec3(mesh.surface.x.row(v).transpose()));
  return box;
}

Camera frame_camera(const std::vector<Drawable>& meshes, double aspect, const Vec3& view_direction,
                    double fov_y_degrees) {
  return frame_camera(mesh_bounds(meshes), aspect, view_direction, fov_y_degrees);
}

void validate_drawable(const Drawable& mesh, std::size_t index) {
  const std::string name = "Drawable " + std::to_string(index);
  const Eigen::Index n = mesh.surface.x.rows();
  for (Eigen::Index v = 0; v < n; ++v)
    if (!mesh.surface.x.row(v).allFinite())
      throw std::invalid_argument(name + ": positions row " + std::to_string(v) + " is not finite");
  for (Eigen::Index f = 0; f < mesh.surface.tris.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.surface.tris(f, k);
      if (v < 0 || v >= n)
        throw std::invalid_argument(name + ": triangles row " + std::to_string(f) + " refers to vertex " +
                                    std::to_string(v) + " but the mesh has " + std::to_string(n) +
                                    " vertices");
    }
  auto check_color = [&](const Vec3& c, const std::string& field) {
    if (!c.allFinite() || c.minCoeff() < 0.0 || c.maxCoeff() > 1.0)
      throw std::invalid_argument(name + ": " + field + " must be RGB in [0, 1]");
  };
  check_color(mesh.color, "color");
  check_color(mesh.back_color, "back_color");
  if (mesh.vertex_scalar.size() > 0 && mesh.face_colors.rows() > 0)
    throw std::invalid_argument(name + ": set vertex_scalar or face_colors, not both");
  if (mesh.vertex_scalar.size() > 0) {
    if (mesh.vertex_scalar.size() != n)
      throw std::invalid_argument(name + ": vertex_scalar has " + std::to_string(mesh.vertex_scalar.size()) +
                                  " values for " + std::to_string(n) + " vertices");
    for (Eigen::Index v = 0; v < n; ++v)
      if (!std::isfinite(mesh.vertex_scalar(v)))
        throw std::invalid_argument(name + ": vertex_scalar[" + std::to_string(v) + "] is not finite");
    if (!std::isfinite(mesh.scalar_min) || !std::isfinite(mesh.scalar_max))
      throw std::invalid_argument(name + ": scalar_min / scalar_max must be finite");
  }
  if (mesh.face_colors.rows() > 0) {
    if (mesh.face_colors.rows() != mesh.surface.tris.rows())
      throw std::invalid_argument(name + ": face_colors has " + std::to_string(mesh.face_colors.rows()) +
                                  " rows for " + std::to_string(mesh.surface.tris.rows()) + " triangles");
    for (Eigen::Index f = 0; f < mesh.face_colors.rows(); ++f)
      check_color(mesh.face_colors.row(f).transpose(), "face_colors row " + std::to_string(f));
  }
}

namespace {

void validate_settings(const RenderSettings& s) {
  if (s.width < 1 || s.height < 1 || s.width > 16384 || s.height > 16384)
    throw std::invalid_argument("RenderSettings: width x height " + std::to_string(s.width) + "x" +
                                std::to_string(s.height) + " is outside 1..16384");
  if (s.msaa_samples < 0 || s.msaa_samples > 64)
    throw std::invalid_argument("RenderSettings: msaa_samples " + std::to_string(s.msaa_samples) +
                                " is outside 0..64");
}

// Grid spacing from the 1-2-5 series closest to a quarter of the scene radius, so a few cells
// span the objects whatever their scale.
double grid_spacing(double radius) {
  const double want = radius / 4.0;
  const double decade = std::pow(10.0, std::floor(std::log10(want)));
  double best = decade;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (std::abs(std::log(m * decade / want)) < std::abs(std::log(best / want))) best = m * decade;
  return best;
}

void set_matrix(GLuint program, const char* name, const Eigen::Matrix4d& m) {
  const Eigen::Matrix4f mf = m.cast<float>();  // column-major, as GL expects
  glUniformMatrix4fv(glGetUniformLocation(program, name), 1, GL_FALSE, mf.data());
}
void set_vec3(GLuint program, const char* name, const Vec3& v) {
  glUniform3f(glGetUniformLocation(program, name), float(v.x()), float(v.y()), float(v.z()));
}

}  // namespace

struct MeshRenderer::GlState {
  GLuint background_program = 0, mesh_program = 0, ground_program = 0;
  GLuint empty_vao = 0, mesh_vao = 0, mesh_vbo = 0, ground_vao = 0, ground_vbo = 0;
  // Multisampled target and its single-sample resolve target.
  GLuint ms_fbo = 0, ms_color = 0, ms_depth = 0, resolve_fbo = 0, resolve_color = 0;
  int fbo_width = 0, fbo_height = 0, fbo_samples = -1;
  GLint max_samples = 0;
  std::vector<float> vertices;
  std::vector<std::uint8_t> readback;

  GlState() {
    background_program = detail::build_program(detail::kBackgroundVertex, detail::kBackgroundFragment, "background");
    mesh_program = detail::build_program(detail::kMeshVertex, detail::kMeshFragment, "mesh");
    ground_program = detail::build_program(detail::kGroundVertex, detail::kGroundFragment, "ground");
    glGenVertexArrays(1, &empty_vao);
    glGenVertexArrays(1, &mesh_vao);
    glGenBuffers(1, &mesh_vbo);
    glBindVertexArray(mesh_vao);
    glBindBuffer(GL_ARRAY_BUFFER, mesh_vbo);
    const GLsizei stride = detail::kFloatsPerVertex * sizeof(float);
    for (GLuint attr = 0; attr < 3; ++attr) {
      glEnableVertexAttribArray(attr);
      glVertexAttribPointer(attr, 3, GL_FLOAT, GL_FALSE, stride,
                            reinterpret_cast<const void*>(static_cast<std::uintptr_t>(3 * attr * sizeof(float))));
    }
    glGenVertexArrays(1, &ground_vao);
    glGenBuffers(1, &ground_vbo);
    glBindVertexArray(ground_vao);
    glBindBuffer(GL_ARRAY_BUFFER, ground_vbo);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
    glBindVertexArray(0);
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
    check_gl("renderer set-up");
  }

  void release_framebuffers() {
    glDeleteFramebuffers(1, &ms_fbo);
    glDeleteFramebuffers(1, &resolve_fbo);
    glDeleteRenderbuffers(1, &ms_color);
    glDeleteRenderbuffers(1, &ms_depth);
    glDeleteRenderbuffers(1, &resolve_color);
    ms_fbo = resolve_fbo = ms_color = ms_depth = resolve_color = 0;
  }

  ~GlState() {
    release_framebuffers();
    glDeleteBuffers(1, &mesh_vbo);
    glDeleteBuffers(1, &ground_vbo);
    glDeleteVertexArrays(1, &empty_vao);
    glDeleteVertexArrays(1, &mesh_vao);
    glDeleteVertexArrays(1, &ground_vao);
    glDeleteProgram(background_program);
    glDeleteProgram(mesh_program);
    glDeleteProgram(ground_program);
  }

  // (Re)creates the framebuffers when the size or sample count changes.
  void ensure_framebuffers(int width, int height, int samples) {
    samples = samples <= 1 ? 0 : std::min(samples, static_cast<int>(max_samples));
    if (width == fbo_width && height == fbo_height && samples == fbo_samples) return;
    release_framebuffers();
    glGenRenderbuffers(1, &ms_color);
    glBindRenderbuffer(GL_RENDERBUFFER, ms_color);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, width, height);
    glGenRenderbuffers(1, &ms_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, ms_depth);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, width, height);
    glGenFramebuffers(1, &ms_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, ms_fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, ms_color);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, ms_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("renderer: multisampled framebuffer " + std::to_string(width) + "x" +
                               std::to_string(height) + " with " + std::to_string(samples) +
                               " samples is incomplete");
    glGenRenderbuffers(1, &resolve_color);
    glBindRenderbuffer(GL_RENDERBUFFER, resolve_color);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glGenFramebuffers(1, &resolve_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, resolve_fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolve_color);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("renderer: resolve framebuffer " + std::to_string(width) + "x" +
                               std::to_string(height) + " is incomplete");
    check_gl("framebuffer creation");
    fbo_width = width;
    fbo_height = height;
    fbo_samples = samples;
  }
};

MeshRenderer::MeshRenderer() : context_(std::make_unique<OSMesaContext>(640, 480)) {
  gl_ = std::make_unique<GlState>();
}

MeshRenderer::~MeshRenderer() {
  // GL objects must be deleted while their context is current, before the context goes.
  try {
    context_->make_current();
  } catch (...) {
  }
  gl_.reset();
  context_.reset();
}

Image MeshRenderer::render(const std::vector<Drawable>& meshes, const Camera& camera,
                           const RenderSettings& settings) {
  validate_settings(settings);
  validate_camera(camera);
  for (std::size_t i = 0; i < meshes.size(); ++i) validate_drawable(meshes[i], i);

  context_->resize(settings.width, settings.height);
  GlState& gl = *gl_;
  gl.ensure_framebuffers(settings.width, settings.height, settings.msaa_samples);

  // Scene shifted to its centre so float vertices keep precision far from the world origin.
  Eigen::AlignedBox3d box = mesh_bounds(meshes);
  if (box.isEmpty()) box.extend(camera.target);
  const Vec3 origin = box.center();
  double radius = 0.5 * box.diagonal().norm();
  if (!(radius > 1e-9 * std::max(1.0, origin.norm()))) radius = 1.0;

  gl.vertices.clear();
  std::vector<std::size_t> first_vertex;
  for (const Drawable& mesh : meshes) {
    first_vertex.push_back(gl.vertices.size() / detail::kFloatsPerVertex);
    detail::append_mesh_vertices(mesh, origin, gl.vertices);
  }
  first_vertex.push_back(gl.vertices.size() / detail::kFloatsPerVertex);

  // Ground: a square of half-size ground_radius around the objects' footprint, at world y = 0.
  const double ground_radius = 5.0 * radius;
  const double ground_y = -origin.y();
  const float gr = static_cast<float>(ground_radius), gy = static_cast<float>(ground_y);
  const float ground_quad[] = {-gr, gy, -gr, gr, gy, -gr, gr, gy, gr, -gr, gy, -gr, gr, gy, gr, -gr, gy, gr};

  // Near and far planes bracket everything drawn (eye-space depth = -z).
  const Eigen::Matrix4d view = view_matrix(camera, origin);
  double zmin = std::numeric_limits<double>::infinity(), zmax = 0.0;
  auto bracket = [&](const Vec3& shifted) {
    const double depth = -(view.block<1, 3>(2, 0).dot(shifted) + view(2, 3));
    zmin = std::min(zmin, depth);
    zmax = std::max(zmax, depth);
  };
  for (int corner = 0; corner < 8; ++corner)
    bracket(box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)) - origin);
  if (settings.ground)
    for (int k = 0; k < 6; ++k) bracket(Vec3(ground_quad[3 * k], ground_quad[3 * k + 1], ground_quad[3 * k + 2]));
  double far_plane = std::max(zmax * 1.02, 1e-6 * radius);
  double near_plane = std::max(zmin * 0.98, far_plane * 1e-4);  // 24-bit depth copes with 1e4
  if (!(far_plane > near_plane)) far_plane = 2.0 * near_plane;
  const double aspect = static_cast<double>(settings.width) / settings.height;
  const Eigen::Matrix4d projection = perspective_matrix(camera.fov_y_degrees, aspect, near_plane, far_plane);

  // Key light from the viewer's upper left and in front; a weaker fill from the right.
  const Vec3 key = Vec3(-0.45, 0.65, 0.62).normalized();
  const Vec3 fill = Vec3(0.7, -0.1, 0.7).normalized();

  glBindFramebuffer(GL_FRAMEBUFFER, gl.ms_fbo);
  glViewport(0, 0, settings.width, settings.height);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glClearColor(0.f, 0.f, 0.f, 1.f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  // Background gradient, behind everything.
  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glUseProgram(gl.background_program);
  set_vec3(gl.background_program, "u_top", Vec3(0.95, 0.96, 0.98));
  set_vec3(gl.background_program, "u_bottom", Vec3(0.76, 0.80, 0.86));
  glBindVertexArray(gl.empty_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);

  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);

  if (!gl.vertices.empty()) {
    glUseProgram(gl.mesh_program);
    set_matrix(gl.mesh_program, "u_view", view);
    set_matrix(gl.mesh_program, "u_projection", projection);
    set_vec3(gl.mesh_program, "u_key_direction", key);
    set_vec3(gl.mesh_program, "u_fill_direction", fill);
    glBindVertexArray(gl.mesh_vao);
    glBindBuffer(GL_ARRAY_BUFFER, gl.mesh_vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(gl.vertices.size() * sizeof(float)),
                 gl.vertices.data(), GL_STREAM_DRAW);
    for (std::size_t i = 0; i < meshes.size(); ++i) {
      const Drawable& mesh = meshes[i];
      const bool custom = mesh.vertex_scalar.size() > 0 || mesh.face_colors.rows() > 0;
      set_vec3(gl.mesh_program, "u_back_color", mesh.back_color);
      glUniform1f(glGetUniformLocation(gl.mesh_program, "u_back_mix"),
                  mesh.two_sided ? (custom ? 0.5f : 1.0f) : 0.0f);
      const auto count = static_cast<GLsizei>(first_vertex[i + 1] - first_vertex[i]);
      if (count > 0) glDrawArrays(GL_TRIANGLES, static_cast<GLint>(first_vertex[i]), count);
    }
  }

  if (settings.ground) {
    // After the meshes, blended, so its faded rim mixes into the background only.
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glUseProgram(gl.ground_program);
    set_matrix(gl.ground_program, "u_view", view);
    set_matrix(gl.ground_program, "u_projection", projection);
    glUniform2f(glGetUniformLocation(gl.ground_program, "u_origin_xz"), float(origin.x()), float(origin.z()));
    glUniform2f(glGetUniformLocation(gl.ground_program, "u_center_xz"), 0.f, 0.f);
    glUniform1f(glGetUniformLocation(gl.ground_program, "u_radius"), gr);
    glUniform1f(glGetUniformLocation(gl.ground_program, "u_spacing"), float(grid_spacing(radius)));
    set_vec3(gl.ground_program, "u_ground_color", Vec3(0.86, 0.87, 0.88));
    set_vec3(gl.ground_program, "u_line_color", Vec3(0.55, 0.58, 0.62));
    glBindVertexArray(gl.ground_vao);
    glBindBuffer(GL_ARRAY_BUFFER, gl.ground_vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof ground_quad, ground_quad, GL_STREAM_DRAW);
    glDrawArrays(GL_TRIANGLES, 0, 6);
    glDisable(GL_BLEND);
  }
  glBindVertexArray(0);

  // Resolve MSAA, read back, flip rows (GL's origin is bottom-left, Image's top-left).
  glBindFramebuffer(GL_READ_FRAMEBUFFER, gl.ms_fbo);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, gl.resolve_fbo);
  glBlitFramebuffer(0, 0, settings.width, settings.height, 0, 0, settings.width, settings.height,
                    GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, gl.resolve_fbo);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  Image image(settings.width, settings.height);
  gl.readback.resize(image.rgb.size());
  glReadPixels(0, 0, settings.width, settings.height, GL_RGB, GL_UNSIGNED_BYTE, gl.readback.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  check_gl("rendering a frame");
  const std::size_t row = 3 * static_cast<std::size_t>(settings.width);
  for (int y = 0; y < settings.height; ++y)
    std::copy_n(gl.readback.data() + (settings.height - 1 - y) * row, row, image.pixel(0, y));

  if (!settings.caption.empty()) {
    const int scale = std::max(1, settings.height / 360);
    const int band = (kGlyphHeight + 6) * scale;
    darken_band(image, settings.height - band, settings.height, 0.45);
    draw_text(image, 4 * scale, settings.height - band + 3 * scale, settings.caption, {255, 255, 255}, scale);
  }
  return image;
}

}  // namespace invfem::renders
