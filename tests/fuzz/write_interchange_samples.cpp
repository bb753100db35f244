// Writes one small sample of each interchange format (PLY binary and ASCII, VTU + PVD, USDA) into
// the directory given, for check_interchange.py: a second, independent reader of our output.
// The geometry is fixed so the checker knows the counts: a 2 x 1 x 1 block of 6-tet cubes and
// its 3 x 2 grid surface animated over 3 frames.
#include <cmath>
#include <filesystem>
#include <iostream>

#include "invfem/core/io/ply_writer.hpp"
#include "invfem/core/io/usd_writer.hpp"
#include "invfem/core/io/vtu_writer.hpp"

using namespace invfem;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: write_interchange_samples DIR\n";
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  try {
    std::filesystem::create_directories(dir);
    // 3 x 2 nodes in the plane z = 0, 2 x 1 quads, 4 triangles.
    Points s(6, 3);
    s << 0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0;
    Tris t(4, 3);
    t << 0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4;
    write_ply((dir / "sample_binary.ply").string(), s, t);
    write_ply((dir / "sample_ascii.ply").string(), s, t, PlyEncoding::ascii);

    UsdaAnimationWriter usd((dir / "sample.usda").string(), "sheet", t, 30);
    for (int f = 0; f < 3; ++f) {
      Points x = s;
      x.col(2).array() += 0.1 * f * x.col(0).array();
      usd.add_frame(f, x);
    }

    // 12 nodes (3 x 2 x 2), 2 cubes, 12 tets: each cube as 6 tets around its diagonal.
    Points X(12, 3);
    for (int k = 0, i = 0; k < 2; ++k)
      for (int j = 0; j < 2; ++j)
        for (int a = 0; a < 3; ++a, ++i) X.row(i) << a, j, k;
    auto id = [](int a, int j, int k) { return (k * 2 + j) * 3 + a; };
    Tets tets(12, 4);
    static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    int e = 0;
    for (int c = 0; c < 2; ++c)
      for (const auto& p : perms) {
        int v[3] = {c, 0, 0};
        tets(e, 0) = id(v[0], v[1], v[2]);
        for (int q = 0; q < 3; ++q) {
          ++v[p[q]];
          tets(e, q + 1) = id(v[0], v[1], v[2]);
        }
        ++e;
      }
    PvdWriter pvd((dir / "sample.pvd").string());
    for (int f = 0; f < 2; ++f) {
      VtuFields fields;
      fields.cell_scalars["det_F"] = Eigen::VectorXd::LinSpaced(12, -0.5 + f, 1.5);
      fields.cell_scalars["inverted"] = (fields.cell_scalars["det_F"].array() < 0).cast<double>();
      fields.point_vectors["velocity"] = X * (0.5 * f);
      const std::string name = "sample_" + std::to_string(f) + ".vtu";
      write_vtu((dir / name).string(), X * (1 + 0.1 * f), tets, fields);
      pvd.add(f / 30.0, name);
    }
  } catch (const std::exception& e) {
    std::cerr << "write_interchange_samples: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
