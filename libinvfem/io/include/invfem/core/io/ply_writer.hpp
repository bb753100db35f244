#pragma once
// Stanford PLY output of a triangle surface, written atomically (tmp + rename).
#include <string>

#include "invfem/core/math/types.hpp"

namespace invfem {

enum class PlyEncoding { binary_little_endian, ascii };

// One "vertex" element (double x, y, z: exact in binary, %.17g in ASCII) and one "face" element
// ("property list uchar int vertex_indices", 0-based, corners in the order of `tris`). Binary is
// little-endian whatever the host. Throws std::invalid_argument naming the path for a non-finite
// position or an index outside [0, n); std::runtime_error (from atomic_write) if the file cannot
// be written.
// vertex_uv (#V x 2, or null): per-vertex texture coordinates, as "property double s" and
// "property double t" after z (assimp, Blender and MeshLab read them as UVs).
void write_ply(const std::string& path, const Points& x, const Tris& tris,
               PlyEncoding encoding = PlyEncoding::binary_little_endian,
               const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>* vertex_uv = nullptr);

}  // namespace invfem
