#include "common/deform/intersect.h"

#include <algorithm>
#include <numeric>

namespace tetmvs::deform {

bool segment_crosses_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  // Signed volumes: p and q on strictly opposite sides of the plane, and the line pq
  // passing strictly inside the three edges.
  const auto vol = [](const Eigen::Vector3d& x, const Eigen::Vector3d& y, const Eigen::Vector3d& z,
                      const Eigen::Vector3d& w) { return (y - x).cross(z - x).dot(w - x); };
  const double scale = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (q - p).squaredNorm()});
  const double eps = 1e-12 * scale * std::sqrt(scale);
  const double sp = vol(a, b, c, p), sq = vol(a, b, c, q);
  if (!((sp > eps && sq < -eps) || (sp < -eps && sq > eps))) return false;
  const double s1 = vol(p, q, a, b), s2 = vol(p, q, b, c), s3 = vol(p, q, c, a);
  return (s1 > eps && s2 > eps && s3 > eps) || (s1 < -eps && s2 < -eps && s3 < -eps);
}

namespace {

struct Box {
  Eigen::Vector3d lo, hi;
  bool overlaps(const Box& o) const {
    return (lo.array() <= o.hi.array()).all() && (o.lo.array() <= hi.array()).all();
  }
};

struct Tree {
  struct Node {
    Box box;
    int left = -1, right = -1, start = 0, count = 0;
  };
  std::vector<Node> nodes;
  std::vector<int> prims;
  const std::vector<Box>* boxes = nullptr;

  int build(int s, int e, std::vector<Eigen::Vector3d>& cen) {
    Node n;
    n.box = (*boxes)[prims[s]];
    for (int i = s + 1; i < e; ++i) {
      n.box.lo = n.box.lo.cwiseMin((*boxes)[prims[i]].lo);
      n.box.hi = n.box.hi.cwiseMax((*boxes)[prims[i]].hi);
    }
    const int id = static_cast<int>(nodes.size());
    nodes.push_back(n);
    if (e - s <= 4) {
      nodes[id].start = s;
      nodes[id].count = e - s;
      return id;
    }
    Eigen::Vector3d clo = cen[prims[s]], chi = clo;
    for (int i = s + 1; i < e; ++i) {
      clo = clo.cwiseMin(cen[prims[i]]);
      chi = chi.cwiseMax(cen[prims[i]]);
    }
    int axis;
    (chi - clo).maxCoeff(&axis);
    const int mid = (s + e) / 2;
    std::nth_element(prims.begin() + s, prims.begin() + mid, prims.begin() + e, [&](int x, int y) {
      return cen[x][axis] < cen[y][axis] || (cen[x][axis] == cen[y][axis] && x < y);
    });
    const int l = build(s, mid, cen);
    const int r = build(mid, e, cen);
    nodes[id].left = l;
    nodes[id].right = r;
    return id;
  }
};

int shared_count(const Eigen::Vector3i& t, const Eigen::Vector3i& u, int& ti, int& ui) {
  int n = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (t[i] == u[j]) {
        ++n;
        ti = i;
        ui = j;
      }
  return n;
}

bool triangles_cross(const std::vector<Eigen::Vector3d>& V, const Eigen::Vector3i& t, const Eigen::Vector3i& u) {
  int ti = -1, ui = -1;
  const int sh = shared_count(t, u, ti, ui);
  if (sh >= 2) return false;
  const Eigen::Vector3d &a = V[t[0]], &b = V[t[1]], &c = V[t[2]];
  const Eigen::Vector3d &d = V[u[0]], &e = V[u[1]], &f = V[u[2]];
  if (sh == 1) {
    const Eigen::Vector3d& p1 = V[t[(ti + 1) % 3]];
    const Eigen::Vector3d& p2 = V[t[(ti + 2) % 3]];
    const Eigen::Vector3d& q1 = V[u[(ui + 1) % 3]];
    const Eigen::Vector3d& q2 = V[u[(ui + 2) % 3]];
    return segment_crosses_triangle(p1, p2, d, e, f) || segment_crosses_triangle(q1, q2, a, b, c);
  }
  return segment_crosses_triangle(a, b, d, e, f) || segment_crosses_triangle(b, c, d, e, f) ||
         segment_crosses_triangle(c, a, d, e, f) || segment_crosses_triangle(d, e, a, b, c) ||
         segment_crosses_triangle(e, f, a, b, c) || segment_crosses_triangle(f, d, a, b, c);
}

}  // namespace

std::vector<std::pair<int, int>> self_intersections(const std::vector<Eigen::Vector3d>& V,
                                                    const std::vector<Eigen::Vector3i>& F,
                                                    const std::vector<char>& only_faces) {
  const int nf = static_cast<int>(F.size());
  std::vector<std::pair<int, int>> out;
  if (nf < 2) return out;
  std::vector<Box> boxes(nf);
  std::vector<Eigen::Vector3d> cen(nf);
  for (int f = 0; f < nf; ++f) {
    const auto& a = V[F[f][0]];
    const auto& b = V[F[f][1]];
    const auto& c = V[F[f][2]];
    boxes[f].lo = a.cwiseMin(b).cwiseMin(c);
    boxes[f].hi = a.cwiseMax(b).cwiseMax(c);
    cen[f] = (a + b + c) / 3.0;
  }
  Tree tree;
  tree.boxes = &boxes;
  tree.prims.resize(nf);
  std::iota(tree.prims.begin(), tree.prims.end(), 0);
  tree.nodes.reserve(2 * nf / 2 + 8);
  tree.build(0, nf, cen);
  const bool filter = !only_faces.empty();
  std::vector<std::vector<int>> hits(nf);
  // Filtered: only the listed faces are queried, against every other face; a pair of two
  // listed faces is kept from the query of its lower face.
  std::vector<int> query;
  if (filter) {
    for (int f = 0; f < nf; ++f)
      if (only_faces[f]) query.push_back(f);
  }
  const int nq = filter ? static_cast<int>(query.size()) : nf;
#pragma omp parallel for schedule(dynamic, 256)
  for (int qi = 0; qi < nq; ++qi) {
    const int f = filter ? query[qi] : qi;
    int stack[128];
    int sp = 0;
    stack[sp++] = 0;
    while (sp > 0) {
      const auto& n = tree.nodes[stack[--sp]];
      if (!n.box.overlaps(boxes[f])) continue;
      if (n.left < 0) {
        for (int i = n.start; i < n.start + n.count; ++i) {
          const int g = tree.prims[i];
          if (g == f) continue;
          if (filter ? (only_faces[g] && g < f) : g < f) continue;
          if (!boxes[g].overlaps(boxes[f])) continue;
          if (triangles_cross(V, F[f], F[g])) hits[f].push_back(g);
        }
      } else {
        stack[sp++] = n.left;
        stack[sp++] = n.right;
      }
    }
    std::sort(hits[f].begin(), hits[f].end());
  }
  if (filter) {
    for (int f = 0; f < nf; ++f)
      for (int g : hits[f]) out.emplace_back(std::min(f, g), std::max(f, g));
    std::sort(out.begin(), out.end());
    return out;
  }
  for (int f = 0; f < nf; ++f)
    for (int g : hits[f]) out.emplace_back(f, g);
  return out;
}

}  // namespace tetmvs::deform
