#include "invfem/solids/fracture_pass.hpp"

#include <stdexcept>

#include "invfem/solids/boundary.hpp"
#include "invfem/solids/crack_crossings.hpp"
#include "invfem/solids/embedded_crack_surface.hpp"

namespace invfem {
namespace {

// Per-element material fields follow the copies' root tets.
TetMaterial material_for(const FractureBase& base, const VirtualNodeMesh& m) {
  TetMaterial mat = base.material;
  auto remap = [&](auto& field) {
    if (field.empty()) return;
    auto root = field;
    field.clear();
    for (int r : m.element_root) field.push_back(root[static_cast<std::size_t>(r)]);
  };
  remap(mat.fiber_directions);
  remap(mat.plastic_goal_log);
  return mat;
}

// Starts applied to a copy of a solid's cut mesh, and whether the result may be kept: its new
// surface, with the particles where x has them, is born crossing nothing (crack_crossings.hpp).
struct TrialCut {
  VirtualNodeMesh mesh;
  TopologyChange change;
  int added = 0;       // cut points added (0: nothing to keep)
  bool clean = true;   // no crossing pair born (nothing added is clean)
};

TrialCut trial_cut(const VirtualNodeMesh& mesh, const std::vector<CrackStart>& starts, const Points& x) {
  TrialCut t{mesh, {}, 0, true};
  t.added = apply_crack_starts(t.mesh, starts);
  if (t.added == 0) return t;
  t.change = update_topology(t.mesh);
  std::vector<int> roots;
  for (const CrackStart& c : starts) roots.push_back(mesh.element_root[static_cast<std::size_t>(c.element)]);
  t.clean = !t.change.changed() || crossings_made(t.mesh, t.change, x, roots) == 0;
  return t;
}

}  // namespace

TetSolidForce* rebuild_fractured_solid(SimObject& o, const TetSolidForce& old_force, const VirtualNodeMesh& m,
                                       const FractureBase& base, const TopologyChange* change) {
  const Eigen::Index n = m.num_nodes();
  Points x(n, 3), v(n, 3);
  PlasticState plastic = make_plastic_state(m.num_elements());
  if (change) {
    for (Eigen::Index i = 0; i < n; ++i) {
      const int p = change->parent_node[static_cast<std::size_t>(i)];
      x.row(i) = o.body.x.row(p);
      v.row(i) = o.body.v.row(p);
    }
    for (std::size_t e = 0; e < plastic.Fp_inv.size(); ++e)
      plastic.Fp_inv[e] = old_force.Fp_inv(static_cast<std::size_t>(change->parent_element[e]));
  } else {
    x = rest_positions(m);
    v.setZero();
  }
  auto force = std::make_unique<TetSolidForce>(weighted_tet_rest(m), material_for(base, m));
  force->restore_plastic_state(std::move(plastic));
  TetSolidForce* const made = force.get();
  for (auto& f : o.forces)
    if (f.get() == &old_force) f = std::move(force);
  if (force) throw std::invalid_argument("fracture: object \"" + o.name + "\" does not hold the given tet force");
  o.body.x = std::move(x);
  o.body.v = std::move(v);
  o.body.mass = weighted_lumped_masses(m, base.density);
  o.tets = m.tets;
  const std::string source = o.surface.source;
  o.surface = extract_surface(rest_positions(m), boundary_triangles(m.tets), o.surface_nodes);
  o.surface.source = source;
  // What is written and drawn once a crack opens: the embedded material surface (a copy shows
  // only its side of the cut); before, the boundary as built (bit-identical output).
  o.embedded = has_open_cut(m) ? embedded_material_surface(m, source) : EmbeddedSurface{};
  o.refresh_surface();
  ++o.topology_version;
  // Pins: the original groups, then every copy of each pinned node at its original's anchor.
  std::vector<std::vector<int>> copies(static_cast<std::size_t>(m.root.X.rows()));
  for (int i = static_cast<int>(m.root.X.rows()); i < m.num_nodes(); ++i)
    copies[static_cast<std::size_t>(m.node_root[static_cast<std::size_t>(i)])].push_back(i);
  o.pins = base.pins;
  for (PinGroup& g : o.pins) {
    const std::size_t count = g.nodes.size();
    std::vector<Eigen::Index> rows;
    for (std::size_t k = 0; k < count; ++k)
      for (int c : copies[static_cast<std::size_t>(g.nodes[k])]) {
        g.nodes.push_back(c);
        rows.push_back(static_cast<Eigen::Index>(k));
      }
    if (rows.empty()) continue;
    Points anchors(static_cast<Eigen::Index>(g.nodes.size()), 3);
    anchors.topRows(static_cast<Eigen::Index>(count)) = g.anchors;
    for (std::size_t j = 0; j < rows.size(); ++j)
      anchors.row(static_cast<Eigen::Index>(count + j)) = g.anchors.row(rows[j]);
    g.anchors = std::move(anchors);
  }
  return made;
}

FracturePass::FracturePass(std::vector<FracturingSolid> solids) {
  for (FracturingSolid& s : solids) {
    s.criterion.validate("fracture of \"" + s.object + "\"");
    Solid solid;
    solid.mesh = make_virtual_node_mesh(s.mesh);
    solid.spec = std::move(s);
    solids_.push_back(std::move(solid));
  }
}

void FracturePass::bind(std::vector<SimObject>& objects) {
  for (Solid& s : solids_) {
    if (s.object >= 0) continue;
    for (std::size_t k = 0; k < objects.size(); ++k)
      if (objects[k].name == s.spec.object) s.object = static_cast<int>(k);
    if (s.object < 0) throw std::invalid_argument("fracture: no object \"" + s.spec.object + "\"");
    SimObject& o = objects[static_cast<std::size_t>(s.object)];
    if (o.body.x.rows() != s.spec.mesh.X.rows() || o.tets != s.spec.mesh.tets)
      throw std::invalid_argument("fracture: object \"" + s.spec.object + "\" is not built on the given mesh");
    if (!s.spec.force) throw std::invalid_argument("fracture: object \"" + o.name + "\" has no tet force to fracture");
    s.force = s.spec.force;
    s.base.material = s.force->material();
    s.base.density = s.force->material().density;
    s.base.pins = o.pins;
  }
}

void FracturePass::after_step(std::vector<SimObject>& objects, const StepPassInput& step, FrameReport& report) {
  (void)step, (void)report;
  bind(objects);
  for (Solid& s : solids_) {
    SimObject& o = objects[static_cast<std::size_t>(s.object)];
    const std::vector<CrackStart> starts = find_crack_starts(s.mesh, *s.force, s.spec.criterion);
    if (starts.empty()) continue;
    // A cut whose surface would be born crossing itself is not made (crack_crossings.hpp): all the
    // starts together, else each alone and then those that passed alone together (their faces
    // may meet each other), else none this step.
    TrialCut t = trial_cut(s.mesh, starts, o.body.x);
    if (t.added > 0 && !t.clean) {
      std::vector<CrackStart> kept;
      for (const CrackStart& c : starts)
        if (trial_cut(s.mesh, {c}, o.body.x).clean) kept.push_back(c);
      refused_ += static_cast<int>(starts.size() - kept.size());
      if (kept.empty()) continue;
      t = trial_cut(s.mesh, kept, o.body.x);
      if (!t.clean) {
        refused_ += static_cast<int>(kept.size());
        continue;
      }
    }
    if (t.added == 0) continue;
    s.mesh = std::move(t.mesh);
    if (!t.change.changed()) continue;
    s.force = rebuild_fractured_solid(o, *s.force, s.mesh, s.base, &t.change);
    ++events_;
  }
}

void FracturePass::save_state(StateWriter& out) const {
  out.count(solids_.size());
  for (const Solid& s : solids_) {
    const VirtualNodeMesh& m = s.mesh;
    out.count(m.cuts.size());
    for (const auto& [edge, fraction] : m.cuts) {
      out.pod(static_cast<std::int64_t>(edge.first));
      out.pod(static_cast<std::int64_t>(edge.second));
      out.pod(fraction);
    }
    // The pieces (their fractions depend on the order of the splits) and the copies.
    for (const auto& ps : m.pieces) {
      out.count(ps.size());
      for (const CutPiece& p : ps) {
        out.pod(p.mask);
        out.pod(p.weight);
        out.pod(static_cast<std::int64_t>(p.element));
      }
    }
    out.count(static_cast<std::size_t>(m.num_elements()));
    for (int e = 0; e < m.num_elements(); ++e) {
      for (int k = 0; k < 4; ++k) out.pod(static_cast<std::int64_t>(m.tets(e, k)));
      out.pod(static_cast<std::int64_t>(m.element_root[static_cast<std::size_t>(e)]));
      out.pod(m.material[static_cast<std::size_t>(e)]);
      out.pod(m.weight[static_cast<std::size_t>(e)]);
    }
    out.count(static_cast<std::size_t>(m.num_nodes()));
    for (int r : m.node_root) out.pod(static_cast<std::int64_t>(r));
  }
}

void FracturePass::restore_state(StateReader& in, std::vector<SimObject>& objects) {
  bind(objects);
  if (in.count("the fracturing solid count") != solids_.size())
    throw StateError("the state holds another number of fracturing solids");
  std::vector<VirtualNodeMesh> meshes;
  for (const Solid& s : solids_) {
    const std::string what = "the cut mesh of \"" + s.spec.object + "\"";
    VirtualNodeMesh m = make_virtual_node_mesh(s.spec.mesh);
    const std::int64_t nr = m.root.X.rows(), mr = m.root.tets.rows();
    auto index = [&](std::int64_t hi) {
      const auto i = in.pod<std::int64_t>(what);
      if (i < 0 || i >= hi) throw StateError(what + ": an index is out of range");
      return static_cast<int>(i);
    };
    const std::size_t cuts = in.count(what);
    for (std::size_t c = 0; c < cuts; ++c) {
      const int a = index(nr), b = index(nr);
      const double f = in.pod<double>(what);
      if (!(a < b) || !(f > 0 && f < 1)) throw StateError(what + ": a cut is invalid");
      m.cuts[{a, b}] = f;
    }
    // Element and node counts come after the pieces: read the pieces, check their elements later.
    for (std::int64_t r = 0; r < mr; ++r) {
      const std::size_t count = in.count(what);
      if (count < 1 || count > 4) throw StateError(what + ": a tet has " + std::to_string(count) + " pieces");
      auto& ps = m.pieces[static_cast<std::size_t>(r)];
      ps.clear();
      for (std::size_t k = 0; k < count; ++k) {
        CutPiece p;
        p.mask = in.pod<std::uint8_t>(what);
        p.weight = in.pod<double>(what);
        p.element = static_cast<int>(in.pod<std::int64_t>(what));
        if (p.mask == 0 || p.mask > 0xF || !(p.weight > 0 && p.weight <= 1)) throw StateError(what + ": a piece is invalid");
        ps.push_back(p);
      }
    }
    const std::size_t ne = in.count(what);
    if (ne < static_cast<std::size_t>(mr) || ne > 4 * static_cast<std::size_t>(mr)) throw StateError(what + ": bad element count");
    const std::size_t nn_max = 4 * ne;
    m.tets.resize(static_cast<Eigen::Index>(ne), 4);
    m.element_root.resize(ne);
    m.material.resize(ne);
    m.weight.resize(ne);
    for (std::size_t e = 0; e < ne; ++e) {
      for (int k = 0; k < 4; ++k) m.tets(static_cast<Eigen::Index>(e), k) = index(static_cast<std::int64_t>(nn_max));
      m.element_root[e] = index(mr);
      m.material[e] = in.pod<std::uint8_t>(what);
      m.weight[e] = in.pod<double>(what);
      if (!(m.weight[e] > 0 && m.weight[e] <= 1 + 1e-9)) throw StateError(what + ": a copy's fraction is invalid");
    }
    const std::size_t nn = in.count(what);
    if (nn < static_cast<std::size_t>(nr) || nn > nn_max) throw StateError(what + ": bad node count");
    m.node_root.resize(nn);
    for (std::size_t i = 0; i < nn; ++i) m.node_root[i] = index(nr);
    for (std::size_t e = 0; e < ne; ++e)
      for (int k = 0; k < 4; ++k) {
        const int p = m.tets(static_cast<Eigen::Index>(e), k);
        if (p >= static_cast<int>(nn) || m.node_root[static_cast<std::size_t>(p)] != m.root.tets(m.element_root[e], k))
          throw StateError(what + ": copy " + std::to_string(e) + " does not fit its root tet");
      }
    for (const auto& ps : m.pieces)
      for (const CutPiece& p : ps)
        if (p.element < 0 || static_cast<std::size_t>(p.element) >= ne) throw StateError(what + ": a piece's copy is out of range");
    meshes.push_back(std::move(m));
  }
  for (std::size_t k = 0; k < solids_.size(); ++k) {
    Solid& s = solids_[k];
    s.mesh = std::move(meshes[k]);
    s.force = rebuild_fractured_solid(objects[static_cast<std::size_t>(s.object)], *s.force, s.mesh, s.base, nullptr);
  }
}

}  // namespace invfem
