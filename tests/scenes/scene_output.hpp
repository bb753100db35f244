#pragma once
// Reading what `invfem run` wrote (energies.csv, frame OBJs) and comparing it with goldens.
// Shared by every scene test.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "invfem/renders/image.hpp"
#include "invfem/renders/image_compare.hpp"
#include "invfem/core/io/obj_writer.hpp"
#include "invfem/core/io/obj_file.hpp"

namespace invfem::test {

// energies.csv as columns by header name; every column has one entry per frame.
struct Csv {
  std::vector<std::string> header;
  std::map<std::string, std::vector<double>> columns;
  std::size_t rows() const { return columns.empty() ? 0 : columns.begin()->second.size(); }
  const std::vector<double>& operator[](const std::string& name) const { return columns.at(name); }
};

inline Csv read_csv(const std::filesystem::path& path) {
  Csv csv;
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  std::string line;
  std::getline(in, line);
  std::stringstream hs(line);
  for (std::string h; std::getline(hs, h, ',');) csv.header.push_back(h), csv.columns[h];
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::stringstream ls(line);
    std::string cell;
    for (const auto& h : csv.header) {
      if (!std::getline(ls, cell, ',')) throw std::runtime_error(path.string() + ": short row: " + line);
      csv.columns[h].push_back(std::stod(cell));
    }
  }
  return csv;
}

// One number per line of stats.jsonl: the value of "key": (a top-level integer or real field).
inline std::vector<double> stats_column(const std::filesystem::path& path, const std::string& key) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  std::vector<double> out;
  const std::string tag = "\"" + key + "\":";
  for (std::string line; std::getline(in, line);) {
    const auto at = line.find(tag);
    if (at == std::string::npos) throw std::runtime_error(path.string() + ": a line without " + tag);
    out.push_back(std::stod(line.substr(at + tag.size())));
  }
  return out;
}

// A JSON file the run or a check wrote (scene.json, `invfem check --json` rows in check.json).
inline nlohmann::json read_json(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  return nlohmann::json::parse(in);
}

// Every value of every column is finite (a fatal failure naming the column and frame otherwise;
// call it inside ASSERT_NO_FATAL_FAILURE to stop the test there).
inline void expect_all_finite(const Csv& csv) {
  for (const auto& col : csv.header)
    for (std::size_t i = 0; i < csv[col].size(); ++i)
      ASSERT_TRUE(std::isfinite(csv[col][i])) << col << " at frame " << i;
}

inline bool update_golden() {
  const char* v = std::getenv("INVFEM_UPDATE_GOLDEN");
  return v && std::string(v) == "1";
}

// In update mode, copy `actual` over `golden` and return true (nothing to compare). Otherwise
// require the golden to exist (a fatal failure naming the update command if it does not).
inline bool replace_golden_if_updating(const std::filesystem::path& actual, const std::filesystem::path& golden) {
  if (!update_golden()) return false;
  std::filesystem::create_directories(golden.parent_path());
  std::filesystem::copy_file(actual, golden, std::filesystem::copy_options::overwrite_existing);
  std::cout << "updated golden " << golden << "\n";
  return true;
}

// Compare the listed columns of `actual` with the golden CSV, frame by frame:
// |a - g| <= rtol |g| + atol_frac * max_frames |g| (per column), so columns that pass through
// zero are judged on their own scale. With INVFEM_UPDATE_GOLDEN=1 the golden is rewritten.
inline void expect_matches_golden_csv(const std::filesystem::path& actual_path,
                                      const std::filesystem::path& golden_path,
                                      const std::vector<std::string>& columns, double rtol, double atol_frac) {
  if (replace_golden_if_updating(actual_path, golden_path)) return;
  ASSERT_TRUE(std::filesystem::exists(golden_path))
      << golden_path << " is missing; run INVFEM_UPDATE_GOLDEN=1 tests/run.sh to create it";
  const Csv a = read_csv(actual_path), g = read_csv(golden_path);
  ASSERT_EQ(a.rows(), g.rows()) << "frame count differs from " << golden_path;
  for (const auto& name : columns) {
    const auto& av = a[name];
    const auto& gv = g[name];
    double scale = 0;
    for (double x : gv) scale = std::max(scale, std::abs(x));
    int bad = 0;
    for (std::size_t i = 0; i < gv.size(); ++i) {
      if (std::abs(av[i] - gv[i]) > rtol * std::abs(gv[i]) + atol_frac * scale) {
        if (++bad <= 3)
          ADD_FAILURE() << name << " at frame " << i << ": " << av[i] << ", golden " << gv[i] << " ("
                        << golden_path.filename() << ")";
      }
    }
    EXPECT_EQ(bad, 0) << name << " differs from the golden in " << bad << " frames";
  }
}

inline std::string frame_file(int frame, const char* ext = "obj") {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%04d.%s", frame, ext);
  return buf;
}

// Image regression in the manner of Blender's render tests: fail when more than
// `max_fraction` of the pixels differ by more than `threshold` (0-255, largest channel
// difference). On failure a diff image is written next to the output (NNNN.diff.png).
// llvmpipe rasterizes deterministically, but antialiased edges may shift by a pixel between
// CPUs: the tolerance absorbs that, not a moved object.
inline void expect_matches_golden_png(const std::filesystem::path& actual_path,
                                      const std::filesystem::path& golden_path, int threshold = 24,
                                      double max_fraction = 0.01) {
  if (replace_golden_if_updating(actual_path, golden_path)) return;
  ASSERT_TRUE(std::filesystem::exists(golden_path))
      << golden_path << " is missing; run INVFEM_UPDATE_GOLDEN=1 tests/run.sh to create it";
  const renders::Image a = renders::read_png(actual_path.string());
  const renders::Image g = renders::read_png(golden_path.string());
  ASSERT_EQ(a.width, g.width);
  ASSERT_EQ(a.height, g.height);
  const renders::ImageDiff d = renders::compare_images(a, g, threshold);
  if (d.fraction_over > max_fraction) {
    std::filesystem::path diff = actual_path;
    diff.replace_extension(".diff.png");
    renders::write_png(diff.string(), renders::make_diff_image(a, g, threshold));
    ADD_FAILURE() << actual_path << " differs from " << golden_path << ": " << 100 * d.fraction_over
                  << "% of pixels over " << threshold << " (allowed " << 100 * max_fraction << "%); diff image "
                  << diff;
  }
}

// RMS distance between two point sets after the best rigid alignment (Kabsch), over the
// bounding-box diagonal of `rest`: a shape error free of where the object went.
inline double aligned_shape_error(const Points& rest, const Points& x) {
  const Eigen::RowVector3d cr = rest.colwise().mean(), cx = x.colwise().mean();
  const Eigen::MatrixX3d A = rest.rowwise() - cr, B = x.rowwise() - cx;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(A.transpose() * B, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  const Eigen::Matrix3d R = svd.matrixV() * D * svd.matrixU().transpose();  // B ~ A R^T
  const double rms = std::sqrt((B - A * R.transpose()).rowwise().squaredNorm().mean());
  const double diag = (rest.colwise().maxCoeff() - rest.colwise().minCoeff()).norm();
  return rms / diag;
}

// A scene that switched to the implicit integrator, against its run with the ITF04 step
// (ITF04_REFERENCE in tests/scenes/CMakeLists.txt, written to `reference`), at the last frame:
// the gravity potential within gravity_tol of the reference's largest drop from frame 0, and the
// vertices of `object` at a mean distance within shape_tol of the object's size (bounding-box
// diagonal). Large backward-Euler steps damp a swing and shift a motion, so a fold lands
// elsewhere: the tolerances are the scene's stated ones, not roundoff. The largest gravity
// difference over all frames is recorded (gravity_vs_itf04_worst_frame).
inline void expect_close_to_itf04_reference(const std::filesystem::path& out, const std::filesystem::path& reference,
                                            const std::string& object, int last_frame, double gravity_tol,
                                            double shape_tol) {
  const Csv a = read_csv(out / "energies.csv"), b = read_csv(reference / "energies.csv");
  ASSERT_EQ(a.rows(), b.rows());
  double drop = 0, worst = 0;
  for (std::size_t f = 0; f < b.rows(); ++f) drop = std::max(drop, b["gravity"][0] - b["gravity"][f]);
  ASSERT_GT(drop, 0) << "the reference run does not fall";
  for (std::size_t f = 0; f < a.rows(); ++f) worst = std::max(worst, std::abs(a["gravity"][f] - b["gravity"][f]));
  const double at_end = std::abs(a["gravity"].back() - b["gravity"].back()) / drop;
  EXPECT_LT(at_end, gravity_tol) << "last frame's gravity potential vs the ITF04 step, over the drop of " << drop
                                 << " J";
  const auto last = [&](const std::filesystem::path& dir) {
    return read_obj_surface((dir / "frames" / object / frame_file(last_frame)).string()).x;
  };
  const Points xa = last(out), xb = last(reference);
  ASSERT_EQ(xa.rows(), xb.rows());
  const double size = (xb.colwise().maxCoeff() - xb.colwise().minCoeff()).norm();
  const double mean = (xa - xb).rowwise().norm().mean() / size;
  EXPECT_LT(mean, shape_tol) << "mean vertex distance to the ITF04 step's last frame, over the size " << size << " m";
  ::testing::Test::RecordProperty("gravity_vs_itf04", std::to_string(at_end));
  ::testing::Test::RecordProperty("gravity_vs_itf04_worst_frame", std::to_string(worst / drop));
  ::testing::Test::RecordProperty("shape_vs_itf04", std::to_string(mean));
}

#if defined(INVFEM_SCENE_DIR) && defined(INVFEM_GOLDEN_DIR)
// The golden checks every scene test shares, on what the run of its scene wrote (INVFEM_SCENE_DIR):
// energies.csv against tests/golden/energies/<scene>.csv on `columns` (tolerance 1e-3 relative
// and 1e-3 of each column's scale), and the previews of `frames` against
// tests/golden/images/<scene>/ (regenerated with INVFEM_UPDATE_GOLDEN=1).
inline void expect_energies_match_golden(const std::string& scene,
                                         const std::vector<std::string>& columns = {"kinetic", "elastic", "gravity"}) {
  expect_matches_golden_csv(std::filesystem::path(INVFEM_SCENE_DIR) / "energies.csv",
                            std::filesystem::path(INVFEM_GOLDEN_DIR) / "energies" / (scene + ".csv"), columns, 1e-3, 1e-3);
}
inline void expect_previews_match_golden(const std::string& scene, std::initializer_list<int> frames) {
  for (int f : frames)
    expect_matches_golden_png(std::filesystem::path(INVFEM_SCENE_DIR) / "png" / frame_file(f, "png"),
                              std::filesystem::path(INVFEM_GOLDEN_DIR) / "images" / scene / frame_file(f, "png"));
}
#endif

}  // namespace invfem::test
