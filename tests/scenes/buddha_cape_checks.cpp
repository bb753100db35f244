// ITF04 Figure 5 at a quick resolution: the volumetric Buddha, pinned at its base on the ground,
// wears a cape tied at its upper back (attachments) and collides with it one way (the cloth
// never pushes back). A ball hits its belly: some tets invert and recover, the cape swings out
// and drapes back. Checks what `invfem run apps/scenes/buddha_cape.json --quick`, `invfem check`
// (OUT/check.json) and `invfem render` wrote.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <limits>

#include <nlohmann/json.hpp>

#include "invfem/core/geometry/closest_point.hpp"
#include "scene_output.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;

// Every frame: no cape triangle crosses a Buddha triangle, the cape never crosses itself, and
// the Buddha's boundary never crosses itself, while the ball squashes it too (the boundary is
// handled as a cloth: its tets invert through the interior, collision_mesh.hpp).
TEST(BuddhaCape, NothingCrossesTheBuddhaTheCapeOrItself) {
  const nlohmann::json rows = read_json(kOut / "check.json");
  const Csv csv = read_csv(kOut / "energies.csv");
  ASSERT_EQ(rows.size(), csv.rows());
  for (const auto& row : rows) {
    const int f = row["frame"].get<int>();
    EXPECT_EQ(row["self"]["cape"].get<long long>(), 0) << "frame " << f;
    EXPECT_EQ(row["self"]["buddha"].get<long long>(), 0) << "frame " << f;
    for (const auto& c : row["cross"]) EXPECT_EQ(c["count"].get<long long>(), 0) << "frame " << f << ": " << c;
  }
}

// The attached cape vertices (the scene's box on the cape's frame 0) lie off the Buddha, so each
// is embedded on its closest boundary triangle with an offset (world.hpp Attachment): recomputed
// here from frame 0's surfaces, the embedding must hold in every frame up to the OBJ's rounding.
TEST(BuddhaCape, AttachedVerticesStayOnTheirEmbedding) {
  const nlohmann::json scene = read_json(kOut / "scene.json");
  const auto& box = scene["cloths"][0]["attachments"][0]["box"];
  const Vec3 lo(box["min"][0], box["min"][1], box["min"][2]), hi(box["max"][0], box["max"][1], box["max"][2]);
  const TriangleSurface cape0 = read_obj_surface((kOut / "frames/cape" / frame_file(0)).string());
  const TriangleSurface buddha0 = read_obj_surface((kOut / "frames/buddha" / frame_file(0)).string());
  struct Embedding {
    int vertex;
    Eigen::Vector3i tri;
    Vec3 w, offset;
  };
  std::vector<Embedding> attached;
  for (Eigen::Index i = 0; i < cape0.x.rows(); ++i) {
    const Vec3 p = cape0.x.row(i).transpose();
    if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
    Embedding e{static_cast<int>(i), {}, {}, {}};
    double best = std::numeric_limits<double>::infinity();
    for (Eigen::Index f = 0; f < buddha0.tris.rows(); ++f) {
      const TrianglePoint tp = closest_point_on_triangle(p, buddha0.x.row(buddha0.tris(f, 0)).transpose(),
                                                         buddha0.x.row(buddha0.tris(f, 1)).transpose(),
                                                         buddha0.x.row(buddha0.tris(f, 2)).transpose());
      if (!(tp.distance2 < best)) continue;
      best = tp.distance2;
      e.tri = buddha0.tris.row(f).transpose();
      e.w = tp.barycentric;
      e.offset = p - tp.point;
    }
    EXPECT_GT(std::sqrt(best), 0.0) << "vertex " << i << " lies on the Buddha";
    attached.push_back(e);
  }
  ASSERT_GE(attached.size(), 5u);
  const Csv csv = read_csv(kOut / "energies.csv");
  double worst = 0, moved = 0;
  for (std::size_t f = 0; f < csv.rows(); ++f) {
    const TriangleSurface cape = read_obj_surface((kOut / "frames/cape" / frame_file(static_cast<int>(f))).string());
    const TriangleSurface buddha = read_obj_surface((kOut / "frames/buddha" / frame_file(static_cast<int>(f))).string());
    for (const Embedding& e : attached) {
      Vec3 target = e.offset;
      for (int k = 0; k < 3; ++k) target += e.w(k) * buddha.x.row(e.tri(k)).transpose();
      worst = std::max(worst, (cape.x.row(e.vertex).transpose() - target).norm());
      moved = std::max(moved, (cape.x.row(e.vertex) - cape0.x.row(e.vertex)).norm());
    }
  }
  EXPECT_LT(worst, 1e-6);  // [m]: 9-digit OBJ coordinates
  EXPECT_GT(moved, 0.01);  // the Buddha's sway carried them by more than 1 cm
  RecordProperty("worst_attachment_error_m", std::to_string(worst));
}

// The ball inverts tets; they recover, and the Buddha stands again.
TEST(BuddhaCape, SomeTetsInvertAndRecover) {
  const Csv csv = read_csv(kOut / "energies.csv");
  expect_all_finite(csv);
  const double peak = *std::max_element(csv["inverted"].begin(), csv["inverted"].end());
  EXPECT_GT(peak, 0);
  EXPECT_EQ(csv["inverted"].back(), 0);
  EXPECT_GT(csv["min_det_F"].back(), 0.5);
  const TriangleSurface rest = read_obj_surface((kOut / "frames/buddha" / frame_file(0)).string());
  const TriangleSurface last =
      read_obj_surface((kOut / "frames/buddha" / frame_file(static_cast<int>(csv.rows()) - 1)).string());
  EXPECT_GT(last.x.col(1).maxCoeff(), 0.85 * rest.x.col(1).maxCoeff());  // standing, not lying
}

// stats.jsonl splits each frame's simulation time per object (the share of time in solid, cloth
// and collisions): the Buddha and the cape both take time in every simulated frame, and
// the objects, the coupling and the self-collision layer fit inside the frame's simulate seconds.
// Their CG and Newton iterations ("objects") add up to the frame's.
TEST(BuddhaCape, StatsSplitTheTimePerObject) {
  std::ifstream in(kOut / "stats.jsonl");
  ASSERT_TRUE(in) << "stats.jsonl";
  int frames = 0;
  for (std::string line; std::getline(in, line);) {
    const nlohmann::json r = nlohmann::json::parse(line);
    const auto& sec = r["seconds"];
    ASSERT_TRUE(sec.contains("objects")) << line;
    const auto& obj = sec["objects"];
    ASSERT_EQ(obj.size(), 2u) << line;
    const double buddha = obj["buddha"].get<double>(), cape = obj["cape"].get<double>();
    const double parts = buddha + cape + sec["coupling"].get<double>() + sec["self_collision"].get<double>();
    ASSERT_TRUE(r.contains("objects")) << line;
    const auto& counts = r["objects"];
    for (const char* key : {"cg_iterations", "newton_iterations"})
      EXPECT_EQ(counts["buddha"][key].get<long>() + counts["cape"][key].get<long>(), r[key].get<long>()) << key << ": " << line;
    if (r["frame"].get<int>() == 0) {
      EXPECT_EQ(parts, 0.0);  // frame 0 is the initial state: nothing stepped
      continue;
    }
    ++frames;
    EXPECT_GT(buddha, 0.0) << line;
    EXPECT_GT(cape, 0.0) << line;
    EXPECT_GT(counts["buddha"]["newton_iterations"].get<long>(), 0) << line;
    EXPECT_GT(counts["cape"]["newton_iterations"].get<long>(), 0) << line;
    EXPECT_LE(parts, sec["simulate"].get<double>() * (1 + 1e-9) + 1e-6) << line;
  }
  EXPECT_GT(frames, 0);
}

TEST(BuddhaCape, EnergiesMatchGolden) {
  expect_energies_match_golden("buddha_cape", {"kinetic", "elastic", "gravity", "inverted", "min_det_F", "volume"});
}

// The rest pose, the hit, and the cape draping back.
TEST(BuddhaCape, PreviewsMatchGolden) {
  expect_previews_match_golden("buddha_cape", {0, 11, 24});
}

}  // namespace
}  // namespace invfem::test
