#include "common/trimesh/bvh.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace tetmvs {

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double den = d1 - d3;
    return den > 0 ? Eigen::Vector3d(a + (d1 / den) * ab) : a;
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double den = d2 - d6;
    return den > 0 ? Eigen::Vector3d(a + (d2 / den) * ac) : a;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double den = (d4 - d3) + (d5 - d6);
    return den > 0 ? Eigen::Vector3d(b + ((d4 - d3) / den) * (c - b)) : b;
  }
  const double sum = va + vb + vc;
  if (!(sum > 0)) {  // degenerate triangle: closest of the three edges
    auto seg = [&](const Eigen::Vector3d& s, const Eigen::Vector3d& e) {
      const Eigen::Vector3d d = e - s;
      const double l = d.squaredNorm();
      const double t = l > 0 ? std::clamp((p - s).dot(d) / l, 0.0, 1.0) : 0.0;
      return Eigen::Vector3d(s + t * d);
    };
    Eigen::Vector3d best = seg(a, b);
    for (const Eigen::Vector3d& q : {seg(b, c), seg(c, a)})
      if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
    return best;
  }
  const double v = vb / sum, w = vc / sum;
  return a + ab * v + ac * w;
}

MeshBVH::MeshBVH(const TriMesh& m) {
  points_only_ = m.F.empty();
  const std::size_t n = points_only_ ? m.V.size() : m.F.size();
  require(n > 0, "MeshBVH: empty mesh");
  std::vector<Eigen::Vector3d> cen(n);
  A.resize(n);
  if (!points_only_) {
    B.resize(n);
    C.resize(n);
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (points_only_) {
      A[i] = m.V[i];
      cen[i] = A[i];
    } else {
      A[i] = m.V[m.F[i][0]];
      B[i] = m.V[m.F[i][1]];
      C[i] = m.V[m.F[i][2]];
      cen[i] = (A[i] + B[i] + C[i]) / 3.0;
    }
  }
  prims_.resize(n);
  for (std::size_t i = 0; i < n; ++i) prims_[i] = static_cast<int>(i);
  nodes_.reserve(2 * n / 2 + 1);
  build(0, static_cast<int>(n), cen);
}

int MeshBVH::build(int start, int end, std::vector<Eigen::Vector3d>& cen) {
  const int id = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo, clo = lo, chi = -lo;
  for (int i = start; i < end; ++i) {
    const int p = prims_[i];
    lo = lo.cwiseMin(A[p]);
    hi = hi.cwiseMax(A[p]);
    if (!points_only_) {
      lo = lo.cwiseMin(B[p]).cwiseMin(C[p]);
      hi = hi.cwiseMax(B[p]).cwiseMax(C[p]);
    }
    clo = clo.cwiseMin(cen[p]);
    chi = chi.cwiseMax(cen[p]);
  }
  nodes_[id].lo = lo;
  nodes_[id].hi = hi;
  const int n = end - start;
  int axis;
  const double ext = (chi - clo).maxCoeff(&axis);
  if (n <= 4 || !(ext > 0)) {
    nodes_[id].start = start;
    nodes_[id].count = n;
    return id;
  }
  const int mid = start + n / 2;
  std::nth_element(prims_.begin() + start, prims_.begin() + mid, prims_.begin() + end,
                   [&](int a, int b) { return cen[a][axis] < cen[b][axis] || (cen[a][axis] == cen[b][axis] && a < b); });
  const int l = build(start, mid, cen);
  const int r = build(mid, end, cen);
  nodes_[id].left = l;
  nodes_[id].right = r;
  return id;
}

namespace {
inline double box_dist2(const Eigen::Vector3d& p, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  double d = 0;
  for (int k = 0; k < 3; ++k) {
    const double e = p[k] < lo[k] ? lo[k] - p[k] : (p[k] > hi[k] ? p[k] - hi[k] : 0.0);
    d += e * e;
  }
  return d;
}
}  // namespace

ClosestHit MeshBVH::closest(const Eigen::Vector3d& p, double max_dist) const {
  ClosestHit best;
  if (nodes_.empty()) return best;
  best.dist2 = std::isfinite(max_dist) ? max_dist * max_dist : std::numeric_limits<double>::infinity();
  int stack[128];
  int sp = 0;
  stack[sp++] = 0;
  while (sp > 0) {
    const Node& nd = nodes_[stack[--sp]];
    if (box_dist2(p, nd.lo, nd.hi) > best.dist2) continue;
    if (nd.left < 0) {
      for (int i = nd.start; i < nd.start + nd.count; ++i) {
        const int q = prims_[i];
        const Eigen::Vector3d c = points_only_ ? A[q] : closest_point_on_triangle(p, A[q], B[q], C[q]);
        const double d2 = (c - p).squaredNorm();
        if (d2 < best.dist2 || (d2 == best.dist2 && (best.prim < 0 || q < best.prim))) {
          best.dist2 = d2;
          best.prim = q;
          best.point = c;
        }
      }
      continue;
    }
    const double dl = box_dist2(p, nodes_[nd.left].lo, nodes_[nd.left].hi);
    const double dr = box_dist2(p, nodes_[nd.right].lo, nodes_[nd.right].hi);
    if (dl <= dr) {
      stack[sp++] = nd.right;
      stack[sp++] = nd.left;
    } else {
      stack[sp++] = nd.left;
      stack[sp++] = nd.right;
    }
  }
  if (best.prim < 0) best.dist2 = std::numeric_limits<double>::infinity();
  return best;
}

RayHit MeshBVH::raycast(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double tmin, double tmax) const {
  RayHit hit;
  if (points_only_ || nodes_.empty()) return hit;
  const Eigen::Vector3d inv(1.0 / d.x(), 1.0 / d.y(), 1.0 / d.z());
  double best = tmax;
  int stack[128];
  int sp = 0;
  stack[sp++] = 0;
  while (sp > 0) {
    const Node& nd = nodes_[stack[--sp]];
    double t0 = tmin, t1 = best;
    bool miss = false;
    for (int k = 0; k < 3 && !miss; ++k) {
      double a = (nd.lo[k] - o[k]) * inv[k], b = (nd.hi[k] - o[k]) * inv[k];
      if (a > b) std::swap(a, b);
      if (std::isnan(a) || std::isnan(b)) continue;  // ray parallel and on the slab plane
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
      if (t0 > t1) miss = true;
    }
    if (miss) continue;
    if (nd.left < 0) {
      for (int i = nd.start; i < nd.start + nd.count; ++i) {
        const int q = prims_[i];
        const Eigen::Vector3d e1 = B[q] - A[q], e2 = C[q] - A[q];
        const Eigen::Vector3d pv = d.cross(e2);
        const double det = e1.dot(pv);
        if (det == 0) continue;
        const double id = 1.0 / det;
        const Eigen::Vector3d tv = o - A[q];
        const double u = tv.dot(pv) * id;
        if (u < 0 || u > 1) continue;
        const Eigen::Vector3d qv = tv.cross(e1);
        const double v = d.dot(qv) * id;
        if (v < 0 || u + v > 1) continue;
        const double t = e2.dot(qv) * id;
        if (t > tmin && (t < best || (t == best && q < hit.face))) {
          best = t;
          hit.t = t;
          hit.face = q;
          hit.b1 = u;
          hit.b2 = v;
        }
      }
      continue;
    }
    stack[sp++] = nd.right;
    stack[sp++] = nd.left;
  }
  return hit;
}

bool MeshBVH::inside(const Eigen::Vector3d& p) const {
  if (nodes_.empty() || points_only_) return false;
  if ((p.array() < nodes_[0].lo.array()).any() || (p.array() > nodes_[0].hi.array()).any()) return false;
  static const Eigen::Vector3d dirs[3] = {Eigen::Vector3d(0.5773, 0.3111, 0.7549).normalized(),
                                          Eigen::Vector3d(-0.2718, 0.8813, -0.3871).normalized(),
                                          Eigen::Vector3d(0.6931, -0.5209, -0.4983).normalized()};
  int votes = 0;
  for (const auto& d : dirs) {
    int n = 0;
    double t = 0;
    for (;;) {
      const RayHit h = raycast(p, d, t);
      if (h.face < 0) break;
      ++n;
      t = h.t + 1e-9;
    }
    votes += n % 2;
  }
  return votes >= 2;
}

}  // namespace tetmvs
