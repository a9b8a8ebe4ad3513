// The 14 canonical patch orientations of the paper (section 2.3): the 6 axis
// directions (cube faces) and the 8 cube diagonals (cube corners), unit length.
// Index order: +x, -x, +y, -y, +z, -z, then (sx, sy, sz)/sqrt(3) for
// sx, sy, sz in {+,-} with x varying slowest: (+++), (++-), (+-+), (+--), (-++), ...
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>

namespace tetmvs::photo {

inline constexpr int kNumOrientations = 14;
inline constexpr std::uint16_t kAllOrientations = (1u << kNumOrientations) - 1;

inline const std::array<Eigen::Vector3d, kNumOrientations>& orientations() {
  static const std::array<Eigen::Vector3d, kNumOrientations> dirs = [] {
    std::array<Eigen::Vector3d, kNumOrientations> d;
    d[0] = {1, 0, 0};
    d[1] = {-1, 0, 0};
    d[2] = {0, 1, 0};
    d[3] = {0, -1, 0};
    d[4] = {0, 0, 1};
    d[5] = {0, 0, -1};
    int i = 6;
    for (int sx : {1, -1})
      for (int sy : {1, -1})
        for (int sz : {1, -1}) d[i++] = Eigen::Vector3d(sx, sy, sz).normalized();
    return d;
  }();
  return dirs;
}

// Index of the orientation closest in angle to n (largest dot product; ties -> lowest index).
inline int nearest_orientation(const Eigen::Vector3d& n) {
  int best = 0;
  double bd = -2;
  for (int i = 0; i < kNumOrientations; ++i) {
    const double d = orientations()[i].dot(n);
    if (d > bd) bd = d, best = i;
  }
  return best;
}

// Orientation o and its neighbours, as a mask (bit i = orientations()[i]): the orientations
// within 55 degrees of it (an axis direction's four diagonals, a diagonal's three axes), the
// ones a normal closer to o than to any other orientation can be nearest to second.
inline std::uint16_t orientation_and_neighbours(int o) {
  std::uint16_t m = 0;
  for (int i = 0; i < kNumOrientations; ++i)
    if (orientations()[i].dot(orientations()[o]) > 0.5) m |= static_cast<std::uint16_t>(1u << i);
  return m;
}

// A unit vector perpendicular to unit n that depends only on n: n x e_a normalized,
// e_a the coordinate axis along which n has its smallest |component| (lowest index on ties).
inline Eigen::Vector3d stable_perpendicular(const Eigen::Vector3d& n) {
  const Eigen::Vector3d a = n.cwiseAbs();
  int ax = 0;
  if (a[1] < a[ax]) ax = 1;
  if (a[2] < a[ax]) ax = 2;
  return n.cross(Eigen::Vector3d::Unit(ax)).normalized();
}

}  // namespace tetmvs::photo
