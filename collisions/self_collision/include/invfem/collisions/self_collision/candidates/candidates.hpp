#pragma once
// Candidate pairs: the plain data between detection (broad_phase/) and response (response/), in
// the manner of ipc-toolkit. Indices are global in a CollisionMesh. Adjacent pairs (sharing a
// vertex, or holding two vertices a seam welds: collision_mesh.hpp) never appear; neither do pairs with no movable
// vertex. Sorted, without repeats, so every
// consumer visits them in one fixed order (deterministic results at any thread count).
#include <vector>

namespace invfem::collisions {

struct VertexFaceCandidate {
  int vertex = -1, face = -1;
  friend bool operator<(const VertexFaceCandidate& a, const VertexFaceCandidate& b) {
    return a.vertex != b.vertex ? a.vertex < b.vertex : a.face < b.face;
  }
  friend bool operator==(const VertexFaceCandidate& a, const VertexFaceCandidate& b) {
    return a.vertex == b.vertex && a.face == b.face;
  }
};

struct EdgeEdgeCandidate {
  int edge_a = -1, edge_b = -1;  // edge_a < edge_b
  friend bool operator<(const EdgeEdgeCandidate& a, const EdgeEdgeCandidate& b) {
    return a.edge_a != b.edge_a ? a.edge_a < b.edge_a : a.edge_b < b.edge_b;
  }
  friend bool operator==(const EdgeEdgeCandidate& a, const EdgeEdgeCandidate& b) {
    return a.edge_a == b.edge_a && a.edge_b == b.edge_b;
  }
};

struct Candidates {
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  void clear() {
    vf.clear();
    ee.clear();
  }
  std::size_t size() const { return vf.size() + ee.size(); }
};

}  // namespace invfem::collisions
