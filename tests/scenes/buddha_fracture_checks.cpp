// buddha_fracture (issue 13, ITF04 Figure 9): the volumetric Buddha, its base held and its head
// and shoulders (rest y > 0.72 m) pulled up (3 cm over 0.2 s, then 0.3 m/s), flows plastically (ITF04 6.3, Fp limited
// to stretches of 1.6) and then tears through its belly along the scene's seed plane (y = 0.46 m,
// thresholds x 0.08 there) into two pieces; the virtual node algorithm never deletes an element,
// so the rest volume (and the mass) stay exact. Checks what `invfem run
// apps/scenes/buddha_fracture.json --quick` wrote (30 frames at 30 fps, about 3,100 tets).
#include <gtest/gtest.h>

#include <algorithm>

#include "scene_output.hpp"
#include "surface_pieces.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;
constexpr double kPull = 0.3, kFps = 30, kSeedY = 0.46;  // [m/s] of the upper pins, frames/s, [m]

// How far the upper pins have moved at time t [m]: 3 cm over the first 0.2 s, then 0.3 m/s.
double lift(double t) { return t < 0.2 ? 0.03 * t / 0.2 : 0.03 + kPull * (t - 0.2); }
constexpr int kLast = 30;

TriangleSurface frame(int f) { return read_obj_surface((kOut / "frames/buddha" / frame_file(f)).string()); }

// The pieces of a surface, largest first.
std::vector<Piece> pieces(const TriangleSurface& s) {
  std::vector<Piece> out = surface_pieces(s);
  std::sort(out.begin(), out.end(), [](const Piece& a, const Piece& b) { return a.vertices > b.vertices; });
  return out;
}

// One body while it flows and the first cuts start the crack (frame 5): at most chips of a tet,
// which the first cuts shed where the BCC mesh's tets meet only at a node.
TEST(BuddhaFracture, WholeWhileItFlows) {
  EXPECT_EQ(pieces(frame(0)).size(), 1u);
  const std::vector<Piece> p = pieces(frame(5));
  int total = 0;
  for (const Piece& q : p) total += q.vertices;
  for (std::size_t k = 1; k < p.size(); ++k) EXPECT_LE(p[k].vertices, 6) << "frame 5 piece " << k;
  EXPECT_GT(p[0].vertices, total - 4 * 6);
}

// The first cut comes after the plastic flow has started (yielded elements in earlier frames).
TEST(BuddhaFracture, FlowsPlasticallyBeforeItCracks) {
  const Csv csv = read_csv(kOut / "energies.csv");
  const std::vector<double> yielded = stats_column(kOut / "stats.jsonl", "yielded");
  ASSERT_EQ(yielded.size(), csv.rows());
  std::size_t first_cut = 1;
  while (first_cut < csv.rows() && csv["elements"][first_cut] == csv["elements"][0]) ++first_cut;
  ASSERT_LT(first_cut, csv.rows()) << "it never cracked";
  EXPECT_GE(first_cut, 3u);
  double most = 0;
  for (std::size_t f = 1; f < first_cut; ++f) most = std::max(most, yielded[f]);
  EXPECT_GT(most, 0.01 * csv["elements"][0]) << "hardly any plastic flow before the first cut";
}

// Two pieces, parted at the seed plane: the lower one on its held base, the upper one carried by
// its pins; anything else is a chip of a tet or two from the crack (below the upper piece), never
// a piece of the pinned head (the tear runs through the body, not at the pins).
TEST(BuddhaFracture, TearsThroughTheBodyIntoTwoPieces) {
  const std::vector<Piece> rest = pieces(frame(0));
  ASSERT_EQ(rest.size(), 1u);
  for (int f : {15, 20, kLast}) {
    const std::vector<Piece> p = pieces(frame(f));
    ASSERT_GE(p.size(), 2u) << "frame " << f;
    int total = 0;
    for (const Piece& q : p) total += q.vertices;
    const Piece& a = p[0].low < p[1].low ? p[0] : p[1];  // lower
    const Piece& b = p[0].low < p[1].low ? p[1] : p[0];  // upper
    EXPECT_GT(a.vertices, total / 4) << "frame " << f;
    EXPECT_GT(b.vertices, total / 4) << "frame " << f;
    EXPECT_NEAR(a.low, rest[0].low, 1e-6) << "frame " << f;
    EXPECT_NEAR(b.high, rest[0].high + lift(f / kFps), 1e-6) << "frame " << f;
    // The crack faces are the copies' outer faces, within an element (1/18 of the height at the
    // quick resolution) of the seed plane, plus the plastic stretch before the tear. (OBJ frames
    // hold 7 digits: positions to 1e-6.)
    EXPECT_LT(a.high, kSeedY + 0.12) << "frame " << f;
    EXPECT_GT(b.low, a.high) << "frame " << f;
    for (std::size_t k = 2; k < p.size(); ++k) {
      EXPECT_LT(p[k].vertices, total / 100) << "frame " << f << " piece " << k;
      EXPECT_LT(p[k].high, b.low) << "frame " << f << " piece " << k;
      EXPECT_GT(p[k].low, -1e-3) << "frame " << f << " piece " << k << " (below the ground)";
    }
  }
  // The parts move apart at the pull's speed once torn.
  const std::vector<Piece> p20 = pieces(frame(20)), p30 = pieces(frame(kLast));
  auto upper_low = [](const std::vector<Piece>& p) { return std::max(p[0].low, p[1].low); };
  EXPECT_NEAR(upper_low(p30) - upper_low(p20), kPull * 10 / kFps, 0.03);
}

TEST(BuddhaFracture, ElementsAreCopiedNeverDeletedAndTheMassIsConserved) {
  const Csv csv = read_csv(kOut / "energies.csv");
  ASSERT_EQ(csv.rows(), static_cast<std::size_t>(kLast + 1));
  ASSERT_NO_FATAL_FAILURE(expect_all_finite(csv));
  const double rest = csv["rest_volume"].front();
  EXPECT_GT(rest, 0.04);  // the Buddha at this scale: about 0.043 m^3 at 18 cells
  for (double v : csv["rest_volume"]) EXPECT_NEAR(v, rest, 1e-12 * rest);
  for (std::size_t f = 1; f < csv.rows(); ++f) EXPECT_GE(csv["elements"][f], csv["elements"][f - 1]);
  // The crossing tets' copies: a few hundred at this resolution, not the whole body.
  EXPECT_GT(csv["elements"].back(), csv["elements"].front() + 50);
  EXPECT_LT(csv["elements"].back(), csv["elements"].front() * 1.25);
}

TEST(BuddhaFracture, EnergiesMatchGolden) {
  expect_energies_match_golden("buddha_fracture", {"kinetic", "elastic", "gravity", "elements", "volume"});
}

// Before, just after and well after the tear.
TEST(BuddhaFracture, PreviewsMatchGolden) {
  expect_previews_match_golden("buddha_fracture", {0, 12, kLast});
}

}  // namespace
}  // namespace invfem::test
