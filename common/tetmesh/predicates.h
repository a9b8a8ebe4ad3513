// Exact geometric predicates on integer (fixed-point) coordinates, with symbolic
// perturbation (simulation of simplicity) for the query points and lines.
//
// Mesh vertices live on an integer lattice (see tetmesh.h). Query points and segments
// are rounded to a finer fixed-point grid (kFixedBits more bits), so every predicate is
// a determinant of integers, evaluated first in double with a conservative error bound
// and, when that cannot decide, exactly in 128-bit integers.
//
// Degenerate cases (a point on a face, a line through a vertex or along an edge) are
// resolved by a symbolic perturbation: the start point P of a query becomes P + e*kSoS1
// and the end point Q becomes Q + e*kSoS2 for an infinitesimal e > 0. The two integer
// vectors are chosen so that no mesh face normal is orthogonal to either of them and no
// mesh edge lies in their span (checked by a unit test for all integer directions with
// components up to 64), so every perturbed predicate is non-zero. Because the
// perturbation is a real (infinitesimally moved) point or line, all predicates agree with
// one another: point location gives exactly one cell, and a ray walk never gets stuck or
// skips a cell.
#pragma once
#include <cmath>
#include <cstdint>

namespace tetmvs::tet {

using i128 = __int128;

struct I3 {
  std::int64_t x = 0, y = 0, z = 0;
};
inline I3 operator-(const I3& a, const I3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline I3 operator+(const I3& a, const I3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline bool operator==(const I3& a, const I3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// Symbolic perturbation directions (see the header comment and test_tetmesh_predicates).
inline constexpr I3 kSoS1{3, 1021, 1048573};
inline constexpr I3 kSoS2{1031, 7, 1048601};

inline int sign_of(i128 v) { return (v > 0) - (v < 0); }

// Exact det[a b c] (columns) for |components| < 2^41.
inline i128 det3_exact(const I3& a, const I3& b, const I3& c) {
  const i128 m0 = static_cast<i128>(b.y) * c.z - static_cast<i128>(b.z) * c.y;
  const i128 m1 = static_cast<i128>(b.z) * c.x - static_cast<i128>(b.x) * c.z;
  const i128 m2 = static_cast<i128>(b.x) * c.y - static_cast<i128>(b.y) * c.x;
  return a.x * m0 + a.y * m1 + a.z * m2;
}

// Sign of det[a b c]: double evaluation with an error bound, exact fallback.
inline int det3_sign(const I3& a, const I3& b, const I3& c) {
  const double ax = static_cast<double>(a.x), ay = static_cast<double>(a.y), az = static_cast<double>(a.z);
  const double bx = static_cast<double>(b.x), by = static_cast<double>(b.y), bz = static_cast<double>(b.z);
  const double cx = static_cast<double>(c.x), cy = static_cast<double>(c.y), cz = static_cast<double>(c.z);
  const double p0 = by * cz, p1 = bz * cy, p2 = bz * cx, p3 = bx * cz, p4 = bx * cy, p5 = by * cx;
  const double d = ax * (p0 - p1) + ay * (p2 - p3) + az * (p4 - p5);
  const double perm = std::fabs(ax) * (std::fabs(p0) + std::fabs(p1)) +
                      std::fabs(ay) * (std::fabs(p2) + std::fabs(p3)) +
                      std::fabs(az) * (std::fabs(p4) + std::fabs(p5));
  const double bound = 1e-13 * perm;  // true error < 8 ulp * perm
  if (d > bound) return 1;
  if (d < -bound) return -1;
  if (perm == 0.0) return 0;
  return sign_of(det3_exact(a, b, c));
}

// orient(a, b, c, d) = det[b-a, c-a, d-a]; > 0 when d is on the side of the normal
// (b-a) x (c-a), i.e. (a, b, c, d) is a positively oriented tetrahedron.
inline int orient_sign(const I3& a, const I3& b, const I3& c, const I3& d) {
  return det3_sign(b - a, c - a, d - a);
}

// orient(a, b, c, P + e*v) for an infinitesimal e > 0: never 0 for mesh faces.
inline int orient_sos(const I3& a, const I3& b, const I3& c, const I3& P, const I3& v) {
  const I3 u = b - a, w = c - a;
  const int s = det3_sign(u, w, P - a);
  if (s != 0) return s;
  return det3_sign(u, w, v);
}

// A query segment P -> Q in fixed-point coordinates, perturbed to (P + e*kSoS1) ->
// (Q + e*kSoS2).
struct Line {
  I3 P, Q, D;  // D = Q - P
  Line() = default;
  Line(const I3& p, const I3& q) : P(p), Q(q), D(q - p) {}
};

// Side of the perturbed line with respect to the directed edge x -> y:
//   side = det[Q - P, x - P, y - P]  (> 0: the line passes the edge on one side, < 0 the
// other). A triangle (x, y, z) is crossed by the line iff side(x,y), side(y,z), side(z,x)
// share one sign; with (x, y, z) oriented along the outward normal of a cell, all > 0 means
// the line leaves the cell through it, all < 0 that it enters. Antisymmetric in (x, y).
inline int line_side(const Line& L, const I3& x, const I3& y) {
  const I3 X = x - L.P, E = y - x;
  const int s0 = det3_sign(L.D, X, E);
  if (s0 != 0) return s0;
  // first order: det[w, X, E] - det[D, v1, E], w = v2 - v1
  const I3 w = kSoS2 - kSoS1;
  const i128 c1 = det3_exact(w, X, E) - det3_exact(L.D, kSoS1, E);
  if (c1 != 0) return sign_of(c1);
  // second order: det[v1, v2, E] (non-zero for every mesh edge)
  return sign_of(det3_exact(kSoS1, kSoS2, E));
}

}  // namespace tetmvs::tet
