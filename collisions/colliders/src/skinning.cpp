#include "invfem/collisions/colliders/skinning.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace invfem {

namespace {

Mat3 cross_matrix(const Vec3& w) {
  Mat3 m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}

// The interval of `times` holding t: keys k and k + 1 with weight a of the second and da/dt;
// before the first key or from the last on, one key held (a = 0, rate 0).
struct KeySpan {
  std::size_t k = 0, next = 0;
  double a = 0, rate = 0;
};

KeySpan span(const std::vector<double>& times, double t) {
  const std::size_t n = times.size();
  if (n == 1 || t <= times.front()) return {0, 0, 0, 0};
  if (t >= times.back()) return {n - 1, n - 1, 0, 0};
  // The interval that starts at or before t: at a key time, the one starting there.
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
  const double length = times[k + 1] - times[k];
  return {k, k + 1, (t - times[k]) / length, 1 / length};
}

// A local transform's components at rest: T(p) R S(s) with s > 0 but for the sign a mirror needs.
struct Trs {
  Vec3 p, s;
  Eigen::Quaterniond q;
};

Trs decompose(const Mat4& m) {
  Trs r;
  r.p = m.block<3, 1>(0, 3);
  Mat3 a = m.block<3, 3>(0, 0);
  r.s = a.colwise().norm().transpose();
  if (a.determinant() < 0) r.s.x() = -r.s.x();
  for (int i = 0; i < 3; ++i)
    if (r.s[i] != 0) a.col(i) /= r.s[i];
  r.q = Eigen::Quaterniond(a).normalized();
  return r;
}

// Linear interpolation of vector keys and its time derivative.
void interpolate(const std::vector<double>& times, const std::vector<Vec3>& keys, double t, Vec3& value, Vec3& rate) {
  const KeySpan s = span(times, t);
  value = (1 - s.a) * keys[s.k] + s.a * keys[s.next];
  rate = (keys[s.next] - keys[s.k]) * s.rate;
}

// Slerp of rotation keys along the shorter arc: R = R_k Rot(a theta, n) with n, theta the axis and
// angle of q_k^-1 q_k+1, so dR/dt = R [theta n da/dt]x.
void interpolate(const std::vector<double>& times, const std::vector<Eigen::Quaterniond>& keys, double t, Mat3& value,
                 Mat3& rate) {
  const KeySpan s = span(times, t);
  const Eigen::Quaterniond q0 = keys[s.k];
  Eigen::Quaterniond q1 = keys[s.next];
  if (q0.dot(q1) < 0) q1.coeffs() = -q1.coeffs();
  const Eigen::AngleAxisd relative(q0.conjugate() * q1);
  const Mat3 r = (q0 * Eigen::Quaterniond(Eigen::AngleAxisd(s.a * relative.angle(), relative.axis()))).toRotationMatrix();
  value = r;
  rate = r * cross_matrix(relative.axis() * (relative.angle() * s.rate));
}

}  // namespace

SkeletonPose pose_skeleton(const SkinnedCharacter& c, const AnimationClip* clip, double time) {
  const std::size_t n = c.nodes.size();
  std::vector<Mat4> local(n), local_rate(n, Mat4::Zero());
  for (std::size_t i = 0; i < n; ++i) local[i] = c.nodes[i].rest;
  if (clip)
    for (const NodeTrack& track : clip->tracks) {
      const auto node = static_cast<std::size_t>(track.node);
      const Trs rest = decompose(c.nodes[node].rest);
      Vec3 p = rest.p, dp = Vec3::Zero(), s = rest.s, ds = Vec3::Zero();
      Mat3 r = rest.q.toRotationMatrix(), dr = Mat3::Zero();
      if (!track.positions.empty()) interpolate(track.position_times, track.positions, time, p, dp);
      if (!track.rotations.empty()) interpolate(track.rotation_times, track.rotations, time, r, dr);
      if (!track.scales.empty()) interpolate(track.scale_times, track.scales, time, s, ds);
      Mat4 l = Mat4::Identity(), dl = Mat4::Zero();
      l.block<3, 3>(0, 0) = r * s.asDiagonal();
      l.block<3, 1>(0, 3) = p;
      dl.block<3, 3>(0, 0) = dr * s.asDiagonal() + r * ds.asDiagonal();
      dl.block<3, 1>(0, 3) = dp;
      local[node] = l;
      local_rate[node] = dl;
    }
  SkeletonPose pose;
  pose.global.resize(n);
  pose.global_rate.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const int parent = c.nodes[i].parent;
    if (parent < 0) {
      pose.global[i] = local[i];
      pose.global_rate[i] = local_rate[i];
    } else {
      const auto p = static_cast<std::size_t>(parent);
      pose.global[i] = pose.global[p] * local[i];
      pose.global_rate[i] = pose.global_rate[p] * local[i] + pose.global[p] * local_rate[i];
    }
  }
  return pose;
}

void skin_vertices(const SkinnedCharacter& c, const SkeletonPose& pose, Points& x, Points* v) {
  std::vector<Mat4> m(c.bones.size()), dm(c.bones.size());
  for (std::size_t b = 0; b < c.bones.size(); ++b) {
    const auto node = static_cast<std::size_t>(c.bones[b].node);
    m[b] = pose.global[node] * c.bones[b].offset;
    dm[b] = pose.global_rate[node] * c.bones[b].offset;
  }
  const Eigen::Index count = c.bind.rows();
  x.resize(count, 3);
  if (v) v->resize(count, 3);
  for (Eigen::Index i = 0; i < count; ++i) {
    const Eigen::Vector4d X(c.bind(i, 0), c.bind(i, 1), c.bind(i, 2), 1.0);
    Eigen::Vector4d xi = Eigen::Vector4d::Zero(), vi = Eigen::Vector4d::Zero();
    const int first = c.influence_start[static_cast<std::size_t>(i)], last = c.influence_start[static_cast<std::size_t>(i) + 1];
    if (first == last) {
      const auto node = static_cast<std::size_t>(c.mesh_node[static_cast<std::size_t>(i)]);
      xi = pose.global[node] * X;
      vi = pose.global_rate[node] * X;
    }
    for (int k = first; k < last; ++k) {
      const Influence& f = c.influences[static_cast<std::size_t>(k)];
      xi += f.weight * (m[static_cast<std::size_t>(f.bone)] * X);
      vi += f.weight * (dm[static_cast<std::size_t>(f.bone)] * X);
    }
    x.row(i) = xi.head<3>().transpose();
    if (v) v->row(i) = vi.head<3>().transpose();
  }
}

Points bind_pose(const SkinnedCharacter& c) {
  Points x;
  skin_vertices(c, pose_skeleton(c, nullptr, 0), x);
  return x;
}

}  // namespace invfem
