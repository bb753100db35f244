// Offscreen renderer tests (renders/). OSMesa is a required dependency: if a context cannot be
// created, these tests FAIL with the renderer's message rather than skip.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <numbers>
#include <utility>

#include "invfem/renders/image_compare.hpp"
#include "invfem/renders/mesh_normals.hpp"
#include "invfem/renders/mesh_renderer.hpp"

using namespace invfem;
using namespace invfem::renders;

namespace {

// Unit icosphere by subdividing an icosahedron and pushing vertices to the sphere;
// triangles counter-clockwise seen from outside.
Drawable make_icosphere(int subdivisions, double radius = 1.0, const Vec3& center = Vec3::Zero()) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& p : v) p.normalize();
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                                       {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return midpoint[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& tri : f) {
      const int ab = mid(tri[0], tri[1]), bc = mid(tri[1], tri[2]), ca = mid(tri[2], tri[0]);
      next.push_back({tri[0], ab, ca});
      next.push_back({tri[1], bc, ab});
      next.push_back({tri[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    f = std::move(next);
  }
  Drawable mesh;
  mesh.surface.x.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i) mesh.surface.x.row(i) = (center + radius * v[i]).transpose();
  mesh.surface.tris.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t i = 0; i < f.size(); ++i) mesh.surface.tris.row(i) << f[i][0], f[i][1], f[i][2];
  return mesh;
}

// Pixels whose max channel difference from the background render exceeds 12.
struct Mask {
  std::vector<bool> on;
  int count = 0;
  double cx = 0, cy = 0;  // centroid of pixel centres, row 0 at the top
};
Mask foreground(const Image& image, const Image& background) {
  Mask m;
  m.on.assign(static_cast<std::size_t>(image.width) * image.height, false);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      int d = 0;
      for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(image.pixel(x, y)[c] - background.pixel(x, y)[c]));
      if (d > 12) {
        m.on[static_cast<std::size_t>(y) * image.width + x] = true;
        ++m.count;
        m.cx += x + 0.5;
        m.cy += y + 0.5;
      }
    }
  if (m.count > 0) {
    m.cx /= m.count;
    m.cy /= m.count;
  }
  return m;
}

// Pinhole projection done here independently of the renderer: pixel coordinates (x right,
// y down from the top edge) of world point p.
Vec2 project(const Camera& cam, const Vec3& p, int width, int height) {
  const Vec3 forward = (cam.target - cam.position).normalized();
  const Vec3 right = forward.cross(cam.up).normalized();
  const Vec3 up = right.cross(forward);
  const Vec3 d = p - cam.position;
  const double depth = d.dot(forward);
  const double tan_half = std::tan(cam.fov_y_degrees * std::numbers::pi / 360.0);
  const double aspect = double(width) / height;
  const double ndc_x = d.dot(right) / depth / (tan_half * aspect);
  const double ndc_y = d.dot(up) / depth / tan_half;
  return {0.5 * (ndc_x + 1.0) * width, 0.5 * (1.0 - ndc_y) * height};
}

RenderSettings small_settings(int w = 256, int h = 256) {
  RenderSettings s;
  s.width = w;
  s.height = h;
  s.ground = false;
  return s;
}

Camera front_camera(double distance = 4.0) {
  Camera cam;
  cam.position = Vec3(0, 0, distance);
  cam.target = Vec3::Zero();
  cam.up = Vec3(0, 1, 0);
  cam.fov_y_degrees = 40.0;
  return cam;
}

// With INVFEM_RENDER_TEST_OUT set to a folder, tests save their images there for inspection.
void maybe_save(const std::string& name, const Image& image) {
  if (const char* dir = std::getenv("INVFEM_RENDER_TEST_OUT")) write_png(std::string(dir) + "/" + name + ".png", image);
}

// Renderers are costly to create; the tests share one, which also exercises context reuse.
MeshRenderer& renderer() {
  static MeshRenderer r;
  return r;
}

}  // namespace

TEST(Render, ContextIsCoreProfileWithVersion) {
  OSMesaContext context(64, 48);
  ASSERT_FALSE(context.gl_version().empty());
  const int major = std::stoi(context.gl_version());
  EXPECT_GE(major, 3) << context.gl_version();
  EXPECT_EQ(context.width(), 64);
  EXPECT_EQ(context.buffer().size(), 4u * 64 * 48);
  context.resize(32, 16);
  EXPECT_EQ(context.buffer().size(), 4u * 32 * 16);
}

TEST(Render, SphereIsVisibleAndCentredOnItsProjection) {
  const Vec3 center(0.6, 0.3, -0.2);
  const double radius = 0.5;
  const Camera cam = front_camera();
  const RenderSettings s = small_settings();
  const Image background = renderer().render({}, cam, s);
  const Image image = renderer().render({make_icosphere(4, radius, center)}, cam, s);
  ASSERT_EQ(image.width, 256);
  ASSERT_EQ(image.height, 256);
  const Mask m = foreground(image, background);

  // Expected disc: the angular radius asin(r / d) seen through the same pinhole.
  const double dist = (center - cam.position).norm();
  const double tan_half = std::tan(cam.fov_y_degrees * std::numbers::pi / 360.0);
  const double disc_px = std::tan(std::asin(radius / dist)) / tan_half * 128.0;
  const double disc_area = std::numbers::pi * disc_px * disc_px;
  EXPECT_GT(m.count, 0.85 * disc_area);
  EXPECT_LT(m.count, 1.15 * disc_area);

  // Off-axis perspective moves the silhouette's centre outward by under 2 px here.
  const Vec2 expected = project(cam, center, s.width, s.height);
  EXPECT_NEAR(m.cx, expected.x(), 2.5);
  EXPECT_NEAR(m.cy, expected.y(), 2.5);
  EXPECT_GT(expected.x(), 128.0 + 20.0);  // sanity: the test really is off-centre, right and up
  EXPECT_LT(expected.y(), 128.0 - 10.0);
}

TEST(Render, TopStaysTopAndRightStaysRight) {
  Drawable sphere = make_icosphere(3);
  sphere.face_colors.resize(sphere.surface.tris.rows(), 3);
  for (Eigen::Index f = 0; f < sphere.surface.tris.rows(); ++f) {
    Vec3 c = Vec3::Zero();
    for (int k = 0; k < 3; ++k) c += sphere.surface.x.row(sphere.surface.tris(f, k)).transpose() / 3.0;
    if (c.y() > 0.35) sphere.face_colors.row(f) << 0.95, 0.1, 0.1;       // top: red
    else if (c.x() > 0.35) sphere.face_colors.row(f) << 0.1, 0.9, 0.1;   // +x side: green
    else sphere.face_colors.row(f) << 0.3, 0.3, 0.35;
  }
  const Image image = renderer().render({sphere}, front_camera(), small_settings());
  maybe_save("orientation", image);
  double red_y = 0, green_x = 0, grey_y = 0, grey_x = 0;
  int red = 0, green = 0, grey = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const int r = image.pixel(x, y)[0], g = image.pixel(x, y)[1], b = image.pixel(x, y)[2];
      if (r > g + 60 && r > b + 60) red_y += y, ++red;
      else if (g > r + 60 && g > b + 60) green_x += x, ++green;
      else if (std::abs(r - g) < 12 && r < 140) grey_y += y, grey_x += x, ++grey;
    }
  ASSERT_GT(red, 300);
  ASSERT_GT(green, 300);
  ASSERT_GT(grey, 300);
  EXPECT_LT(red_y / red, grey_y / grey - 20.0) << "top (+y) of the sphere is not at the top of the image";
  EXPECT_GT(green_x / green, grey_x / grey + 20.0) << "+x side of the sphere is not on the right";
}

TEST(Render, TwoSidedQuadShowsBackTintFromBehind) {
  Drawable quad;
  quad.surface.x.resize(4, 3);
  quad.surface.x << -1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0;
  quad.surface.tris.resize(2, 3);
  quad.surface.tris << 0, 1, 2, 0, 2, 3;  // front faces +z
  quad.color = Vec3(0.9, 0.25, 0.2);
  quad.back_color = Vec3(0.2, 0.3, 0.9);
  quad.two_sided = true;
  auto centre = [](const Image& im) { return im.pixel(im.width / 2, im.height / 2); };

  const Image front = renderer().render({quad}, front_camera(3.0), small_settings());
  EXPECT_GT(centre(front)[0], centre(front)[2] + 50);
  const Image back = renderer().render({quad}, front_camera(-3.0), small_settings());
  EXPECT_GT(centre(back)[2], centre(back)[0] + 50) << "back side not in the back tint";

  quad.two_sided = false;  // one-sided: the back keeps the front colour
  const Image back_one_sided = renderer().render({quad}, front_camera(-3.0), small_settings());
  EXPECT_GT(centre(back_one_sided)[0], centre(back_one_sided)[2] + 50);
}

TEST(Render, DegenerateMeshesRenderWithoutNaN) {
  // All vertices equal.
  Drawable point;
  point.surface.x = Points::Constant(6, 3, 0.3);
  point.surface.tris.resize(3, 3);
  point.surface.tris << 0, 1, 2, 3, 4, 5, 0, 2, 4;
  const Points normals = face_normals(point.surface.x, point.surface.tris);
  EXPECT_TRUE(normals.allFinite());
  EXPECT_TRUE(normals.isZero());
  const Camera cam = frame_camera(std::vector<Drawable>{point}, 1.0);
  EXPECT_TRUE(cam.position.allFinite());
  const Image background = renderer().render({}, cam, small_settings());
  const Image image = renderer().render({point}, cam, small_settings());
  EXPECT_LT(compare_images(image, background, 12).pixels_over, 4u);

  // A sphere with zero-area slivers and collinear faces mixed in looks like the sphere alone.
  const Drawable sphere = make_icosphere(3);
  Drawable broken = sphere;
  const Eigen::Index n = broken.surface.tris.rows();
  broken.surface.tris.conservativeResize(n + 3, 3);
  broken.surface.tris.row(n) << 0, 0, 1;
  broken.surface.tris.row(n + 1) << 5, 5, 5;
  broken.surface.x.conservativeResize(broken.surface.x.rows() + 1, 3);
  const Eigen::Index mid = broken.surface.x.rows() - 1;
  broken.surface.x.row(mid) = 0.5 * (broken.surface.x.row(2) + broken.surface.x.row(7));
  broken.surface.tris.row(n + 2) << 2, 7, static_cast<int>(mid);
  EXPECT_TRUE(face_normals(broken.surface.x, broken.surface.tris).allFinite());
  for (bool smooth : {false, true}) {
    Drawable a = sphere, b = broken;
    a.smooth = b.smooth = smooth;
    const ImageDiff d = compare_images(renderer().render({a}, front_camera(), small_settings()),
                                       renderer().render({b}, front_camera(), small_settings()), 12);
    EXPECT_LT(d.fraction_over, 0.002) << "smooth=" << smooth;
  }
}

TEST(Render, FrameCameraFitsObjectsInWideImage) {
  Drawable blob = make_icosphere(3);
  blob.surface.x.col(0) *= 3.0;  // wide
  blob.surface.x.col(1) += Eigen::VectorXd::Constant(blob.surface.x.rows(), 5.0);
  const RenderSettings s = small_settings(320, 180);
  for (const Vec3& dir : {kDefaultViewDirection, Vec3(0, -1, 0), Vec3(1, 0, 0)}) {
    const Camera cam = frame_camera(std::vector<Drawable>{blob}, 320.0 / 180.0, dir);
    const Image image = renderer().render({blob}, cam, s);
    maybe_save("framed_" + std::to_string(int(dir.x() * 10)) + std::to_string(int(dir.y() * 10)), image);
    const Mask m = foreground(image, renderer().render({}, cam, s));
    int xmin = s.width, xmax = -1, ymin = s.height, ymax = -1;
    for (int y = 0; y < s.height; ++y)
      for (int x = 0; x < s.width; ++x)
        if (m.on[static_cast<std::size_t>(y) * s.width + x]) {
          xmin = std::min(xmin, x), xmax = std::max(xmax, x);
          ymin = std::min(ymin, y), ymax = std::max(ymax, y);
        }
    ASSERT_GT(m.count, 0) << dir.transpose();
    EXPECT_GT(xmin, 0);
    EXPECT_GT(ymin, 0);
    EXPECT_LT(xmax, s.width - 1);
    EXPECT_LT(ymax, s.height - 1);
    EXPECT_TRUE(xmax - xmin > s.width / 2 || ymax - ymin > s.height / 2) << "object framed too small";
  }
}

TEST(Render, ScalarFieldMapsThroughColormap) {
  Drawable sphere = make_icosphere(3);
  sphere.vertex_scalar = sphere.surface.x.col(1);  // y: -1 bottom (blue) .. +1 top (red)
  sphere.scalar_min = -1.0;
  sphere.scalar_max = 1.0;
  sphere.colormap = Colormap::CoolWarm;
  sphere.smooth = true;
  const Image image = renderer().render({sphere}, front_camera(), small_settings());
  maybe_save("scalar_field", image);
  // Mean red minus blue in windows near the top and bottom of the sphere (radius about 91 px).
  auto red_minus_blue = [&](int y0) {
    double sum = 0;
    for (int y = y0; y < y0 + 10; ++y)
      for (int x = 118; x < 138; ++x) sum += image.pixel(x, y)[0] - image.pixel(x, y)[2];
    return sum / 200.0;
  };
  EXPECT_GT(red_minus_blue(128 - 75), 25.0);
  EXPECT_LT(red_minus_blue(128 + 65), -25.0);
}

TEST(Render, ReusesContextAcrossSizesDeterministically) {
  const std::vector<Drawable> scene{make_icosphere(2)};
  RenderSettings s = small_settings(200, 150);
  const Camera cam = frame_camera(scene, 200.0 / 150.0);
  const Image first = renderer().render(scene, cam, s);
  s.width = 96;
  s.height = 64;
  s.msaa_samples = 0;
  const Image other = renderer().render(scene, cam, s);
  EXPECT_EQ(other.width, 96);
  EXPECT_EQ(other.height, 64);
  EXPECT_EQ(other.rgb.size(), 3u * 96 * 64);
  s = small_settings(200, 150);
  const Image again = renderer().render(scene, cam, s);
  EXPECT_EQ(compare_images(first, again, 0).pixels_over, 0u);
}

TEST(Render, MsaaSmoothsEdges) {
  Drawable quad;
  quad.surface.x.resize(4, 3);
  const double a = 0.35;  // tilted in the image plane so its edges are not pixel-aligned
  for (int k = 0; k < 4; ++k) {
    const double t = a + k * std::numbers::pi / 2;
    quad.surface.x.row(k) << std::cos(t), std::sin(t), 0.0;
  }
  quad.surface.tris.resize(2, 3);
  quad.surface.tris << 0, 1, 2, 0, 2, 3;
  quad.color = Vec3(0.1, 0.1, 0.1);
  auto mixed_pixels = [&](int samples) {
    RenderSettings s = small_settings();
    s.msaa_samples = samples;
    const Image im = renderer().render({quad}, front_camera(), s);
    const Image bg = renderer().render({}, front_camera(), s);
    const std::uint8_t* inside = im.pixel(128, 128);
    int mixed = 0;
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x) {
        int to_bg = 0, to_in = 0;
        for (int c = 0; c < 3; ++c) {
          to_bg = std::max(to_bg, std::abs(im.pixel(x, y)[c] - bg.pixel(x, y)[c]));
          to_in = std::max(to_in, std::abs(im.pixel(x, y)[c] - inside[c]));
        }
        if (to_bg > 20 && to_in > 20) ++mixed;
      }
    return mixed;
  };
  const int aliased = mixed_pixels(0);
  const int smoothed = mixed_pixels(4);
  EXPECT_LT(aliased, 20);
  EXPECT_GT(smoothed, 200);  // the quad's perimeter is about 4 * 1.41 * 88 px
}

TEST(Render, GroundAndCaptionAppear) {
  const std::vector<Drawable> scene{make_icosphere(2, 0.5, Vec3(0, 1.0, 0))};
  RenderSettings s = small_settings(256, 192);
  const Camera cam = frame_camera(scene, 256.0 / 192.0, Vec3(0, -0.6, -1));
  const Image without = renderer().render(scene, cam, s);
  s.ground = true;
  const Image with_ground = renderer().render(scene, cam, s);
  // The ground is below the sphere: the bottom rows change, the top rows (sky) do not.
  int bottom_changed = 0, top_changed = 0;
  for (int x = 0; x < s.width; ++x) {
    for (int c = 0; c < 3; ++c) {
      if (std::abs(with_ground.pixel(x, s.height - 3)[c] - without.pixel(x, s.height - 3)[c]) > 6) {
        ++bottom_changed;
        break;
      }
    }
    for (int c = 0; c < 3; ++c) {
      if (std::abs(with_ground.pixel(x, 2)[c] - without.pixel(x, 2)[c]) > 6) {
        ++top_changed;
        break;
      }
    }
  }
  EXPECT_GT(bottom_changed, s.width / 2);
  EXPECT_EQ(top_changed, 0);

  s.caption = "FRAME 12 T=0.50";
  const Image captioned = renderer().render(scene, cam, s);
  maybe_save("ground_caption", captioned);
  int changed_above = 0, changed_band = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x)
      if (captioned.pixel(x, y)[0] != with_ground.pixel(x, y)[0]) (y < s.height - 13 ? changed_above : changed_band)++;
  EXPECT_EQ(changed_above, 0);
  EXPECT_GT(changed_band, 100);
}

TEST(Render, BadInputGivesClearErrors) {
  Drawable mesh = make_icosphere(1);
  mesh.surface.tris(3, 1) = 1000;
  try {
    renderer().render({mesh}, front_camera(), small_settings());
    FAIL() << "out-of-range vertex index accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("Drawable 0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("triangles row 3"), std::string::npos) << e.what();
  }
  mesh = make_icosphere(1);
  mesh.surface.x(2, 1) = std::nan("");
  EXPECT_THROW(renderer().render({mesh}, front_camera(), small_settings()), std::invalid_argument);
  mesh = make_icosphere(1);
  mesh.vertex_scalar = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(renderer().render({mesh}, front_camera(), small_settings()), std::invalid_argument);
  Camera cam = front_camera();
  cam.target = cam.position;
  EXPECT_THROW(renderer().render({}, cam, small_settings()), std::invalid_argument);
  RenderSettings s = small_settings();
  s.width = 0;
  EXPECT_THROW(renderer().render({}, front_camera(), s), std::invalid_argument);
}
