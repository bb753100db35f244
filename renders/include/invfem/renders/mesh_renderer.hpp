#pragma once
// Offscreen preview renderer: triangle surfaces (the core's one surface type) -> RGB image through
// OSMesa (GL 4.5 core on llvmpipe), with MSAA, key + fill + ambient light, two-sided cloth, per-vertex scalar fields
// or per-face colours, an optional y = 0 ground grid and a caption in a built-in bitmap font.
// Knows nothing of the simulator. Draws on the CPU (llvmpipe): its cost grows with the triangles.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "invfem/core/geometry/surface.hpp"
#include "invfem/renders/camera.hpp"
#include "invfem/renders/colormap.hpp"
#include "invfem/renders/image.hpp"
#include "invfem/renders/osmesa_context.hpp"

namespace invfem::renders {

using FaceColors = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

// A triangle surface and how to draw it.
struct Drawable {
  TriangleSurface surface;  // world space (Y-up), counter-clockwise seen from the front
  Vec3 color{0.72, 0.74, 0.78};  // RGB in [0, 1], used when no scalar or face colours are set
  // Two-sided (cloth): the back side is drawn in back_color (or, with scalar / face colours,
  // those colours mixed half-way towards back_color). One-sided meshes show their back side
  // in the front colour, lit from the flipped normal.
  bool two_sided = false;
  Vec3 back_color{0.80, 0.48, 0.36};
  bool smooth = false;  // area-weighted vertex normals instead of flat face normals

  // Optional per-vertex scalar (size n; empty = none) mapped through `colormap`; values are
  // normalized by [scalar_min, scalar_max], or by the data's own range when scalar_min >= scalar_max.
  Eigen::VectorXd vertex_scalar;
  double scalar_min = 0.0;
  double scalar_max = 0.0;
  Colormap colormap = Colormap::CoolWarm;

  // Optional per-face colours (m x 3 RGB in [0, 1]; empty = none), e.g. inverted elements red.
  // Setting both vertex_scalar and face_colors is an error.
  FaceColors face_colors;
};

struct RenderSettings {
  int width = 640;
  int height = 480;
  int msaa_samples = 4;  // 0 or 1 = no antialiasing; clamped to the driver's GL_MAX_SAMPLES
  bool ground = true;    // y = 0 ground plane with a soft grid, fading out around the objects
  std::string caption;   // drawn bottom-left in the built-in 5x7 font; empty = none
};

// Bounding box of all meshes' vertices (empty box if there are none).
Eigen::AlignedBox3d mesh_bounds(const std::vector<Drawable>& meshes);

// frame_camera (camera.hpp) on the meshes' bounding box.
Camera frame_camera(const std::vector<Drawable>& meshes, double aspect,
                    const Vec3& view_direction = kDefaultViewDirection, double fov_y_degrees = 35.0);

// Throws std::invalid_argument naming the mesh (by index) and the field: bad shapes, vertex
// indices out of range, non-finite positions, colours or scalars, a scalar or face-colour
// array of the wrong length.
void validate_drawable(const Drawable& mesh, std::size_t index);

class MeshRenderer {
 public:
  // Creates the OSMesa context (throws std::runtime_error with a clear message if it cannot).
  MeshRenderer();
  ~MeshRenderer();
  MeshRenderer(const MeshRenderer&) = delete;
  MeshRenderer& operator=(const MeshRenderer&) = delete;

  // Renders one frame. Reuses the context and its framebuffers while the size and sample
  // count stay the same. Throws std::invalid_argument on bad meshes, camera or settings.
  Image render(const std::vector<Drawable>& meshes, const Camera& camera,
               const RenderSettings& settings = {});

  const OSMesaContext& context() const { return *context_; }

 private:
  struct GlState;
  std::unique_ptr<OSMesaContext> context_;
  std::unique_ptr<GlState> gl_;
};

}  // namespace invfem::renders
