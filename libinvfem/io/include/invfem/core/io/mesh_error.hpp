#pragma once
// The one exception type for bad mesh input (tet meshes, OBJ). Its message always names the file
// (or the mesh's `source`), the line where meaningful, the node or element, and the problem.
#include <stdexcept>
#include <string>

namespace invfem {

class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace invfem
