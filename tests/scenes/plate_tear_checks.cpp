// plate_tear (issue 13): a notched slab (apps/scenes/data/notched_slab.mesh: 0.12 x 0.07 x
// 0.02 m, a 4 cm slot from the left at 0.03 < y < 0.04) held at y = 0 and pulled up at 5 cm/s at
// y = 0.07, fracturing by the virtual node algorithm. It must tear from the notch's tip along the
// notch plane into two pieces, conserving its rest volume (and so its mass), early in the run.
// Checks what `invfem run apps/scenes/plate_tear.json --quick` wrote (20 frames at 30 fps).
#include <gtest/gtest.h>


#include "scene_output.hpp"
#include "surface_pieces.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;
constexpr double kPull = 0.05, kFps = 30;  // [m/s] of the upper pins, frames per second

TriangleSurface frame(int f) { return read_obj_surface((kOut / "frames/slab" / frame_file(f)).string()); }

TEST(PlateTear, WholeBeforeTheTear) { EXPECT_EQ(surface_pieces(frame(1)).size(), 1u); }

TEST(PlateTear, TearsAlongTheNotchIntoTwoPieces) {
  for (int f : {5, 12, 20}) {
    const auto p = surface_pieces(frame(f));
    ASSERT_EQ(p.size(), 2u) << "frame " << f;
    const double lift = kPull * f / kFps;  // how far the upper pins have moved
    // The lower piece: from its held edge up to the crack, which runs through the notch's cell
    // row (0.03 < y < 0.04 at rest; the embedded surface shows each side of the cut only),
    // relaxed back close to rest.
    EXPECT_NEAR(p[0].low, 0.0, 1e-9) << "frame " << f;
    EXPECT_LT(p[0].high, 0.039) << "frame " << f;
    EXPECT_GT(p[0].high, 0.031) << "frame " << f;
    // The upper piece moves with its pins and starts at the crack's other face.
    EXPECT_NEAR(p[1].high, 0.07 + lift, 1e-9) << "frame " << f;
    EXPECT_GT(p[1].low - lift, 0.031) << "frame " << f;
    EXPECT_LT(p[1].low - lift, 0.039) << "frame " << f;
  }
}

// The written surface (the embedded material surface once torn) is closed and consistently
// oriented in every frame (each edge on two triangles, once in each direction), and encloses the
// slab's volume: the crack's two faces close each piece, and nothing of a cut element's copies
// shows on the other side.
TEST(PlateTear, EveryFrameIsAClosedSurfaceEnclosingTheSlab) {
  for (int f = 0; f <= 20; ++f) {
    const TriangleSurface s = frame(f);
    const SurfaceEdges edges = surface_edges(s.tris, s.x.rows());
    for (Eigen::Index e = 0; e < edges.count(); ++e) {
      ASSERT_EQ(edges.use_count(e), 2) << "frame " << f << ": edge " << edges.vertices(e, 0) << "-" << edges.vertices(e, 1);
      const auto u0 = edges.use(e, 0), u1 = edges.use(e, 1);
      ASSERT_NE(s.tris(u0.triangle, u0.local), s.tris(u1.triangle, u1.local)) << "frame " << f << ": misoriented";
    }
    // 1.6e-4 m^3 at rest; the stretched and relaxing pieces stay within 2% of it (the enlarged
    // mesh's boundary, each cut element's copies whole, enclosed 10% more: 96 tets of 1/6 cm^3).
    EXPECT_NEAR(enclosed_signed_volume(s), 1.6e-4, 3.2e-6) << "frame " << f;
  }
  // Torn, the surface holds the crack's faces: more triangles than the uncut boundary's 504.
  EXPECT_EQ(frame(0).tris.rows(), 504);
  EXPECT_GT(frame(20).tris.rows(), 504);
}

TEST(PlateTear, ElementsAreCopiedNeverDeletedAndTheRestVolumeIsConserved) {
  const Csv csv = read_csv(kOut / "energies.csv");
  ASSERT_EQ(csv.rows(), 21u);
  ASSERT_NO_FATAL_FAILURE(expect_all_finite(csv));
  // 0.12 x 0.07 x 0.02 m less the slot (4 x 1 x 2 cells of 1 cm): 1.6e-4 m^3 at every frame.
  for (double v : csv["rest_volume"]) EXPECT_NEAR(v, 1.6e-4, 1e-12);
  EXPECT_EQ(csv["elements"].front(), 960);
  for (std::size_t f = 1; f < csv.rows(); ++f) EXPECT_GE(csv["elements"][f], csv["elements"][f - 1]);
  // The ligament (x > 4 cm) of the notch's cell row: 8 x 2 cells x 6 tets, each cut once.
  EXPECT_EQ(csv["elements"].back(), 960 + 96);
  for (double n : csv["inverted"]) EXPECT_EQ(n, 0);
}

TEST(PlateTear, EnergiesMatchGolden) {
  expect_energies_match_golden("plate_tear", {"kinetic", "elastic", "volume"});
}

}  // namespace
}  // namespace invfem::test
