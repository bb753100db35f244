#pragma once
// A scalar that varies in time: piecewise-linear keyframes (t_i, value_i), held constant before
// the first and after the last key. Used for time-dependent material strength and activation.
#include <utility>
#include <vector>

namespace invfem {

struct ScalarTrack {
  std::vector<std::pair<double, double>> keys;  // sorted by time, at least one key

  static ScalarTrack constant(double v) { return {{{0.0, v}}}; }

  double at(double t) const {
    if (keys.empty()) return 1.0;
    if (t <= keys.front().first) return keys.front().second;
    for (std::size_t i = 1; i < keys.size(); ++i) {
      if (t <= keys[i].first) {
        const auto& [t0, v0] = keys[i - 1];
        const auto& [t1, v1] = keys[i];
        const double w = t1 > t0 ? (t - t0) / (t1 - t0) : 1.0;
        return v0 + w * (v1 - v0);
      }
    }
    return keys.back().second;
  }
  // The largest value over [t0, t1] (keys inside the interval and both ends).
  double max_over(double t0, double t1) const {
    double m = at(t0) > at(t1) ? at(t0) : at(t1);
    for (const auto& [t, v] : keys)
      if (t > t0 && t < t1 && v > m) m = v;
    return m;
  }
  double max_value() const {
    double m = keys.empty() ? 1.0 : keys.front().second;
    for (const auto& k : keys) m = k.second > m ? k.second : m;
    return m;
  }
};

}  // namespace invfem
