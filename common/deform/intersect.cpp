#include "common/deform/intersect.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "common/error.h"

namespace tetmvs::deform {

bool segment_crosses_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  // Signed volumes: p and q on strictly opposite sides of the plane, and the line pq
  // passing strictly inside the three edges.
  const auto vol = [](const Eigen::Vector3d& x, const Eigen::Vector3d& y, const Eigen::Vector3d& z,
                      const Eigen::Vector3d& w) { return (y - x).cross(z - x).dot(w - x); };
  const Eigen::Vector3d n = (b - a).cross(c - a);  // the plane's, shared by p and q
  const double sp = n.dot(p - a), sq = n.dot(q - a);
  if (!((sp > 0 && sq < 0) || (sp < 0 && sq > 0))) return false;  // the test below fails too
  const double scale = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (q - p).squaredNorm()});
  const double eps = 1e-12 * scale * std::sqrt(scale);
  if (!((sp > eps && sq < -eps) || (sp < -eps && sq > eps))) return false;
  const double s1 = vol(p, q, a, b), s2 = vol(p, q, b, c), s3 = vol(p, q, c, a);
  return (s1 > eps && s2 > eps && s3 > eps) || (s1 < -eps && s2 < -eps && s3 < -eps);
}

namespace {

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
  // an edge crosses a triangle only between vertices strictly on either side of its plane
  // (segment_crosses_triangle's first test, with the same volumes): when one triangle lies
  // wholly on one side of the other's plane, none of its edges need testing
  const auto one_side = [](const Eigen::Vector3d& x, const Eigen::Vector3d& y, const Eigen::Vector3d& z,
                           const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
    const Eigen::Vector3d n = (y - x).cross(z - x);
    const double vp = n.dot(p - x), vq = n.dot(q - x), vr = n.dot(r - x);
    return (vp >= 0 && vq >= 0 && vr >= 0) || (vp <= 0 && vq <= 0 && vr <= 0);
  };
  if (!one_side(d, e, f, a, b, c) &&
      (segment_crosses_triangle(a, b, d, e, f) || segment_crosses_triangle(b, c, d, e, f) ||
       segment_crosses_triangle(c, a, d, e, f)))
    return true;
  return !one_side(a, b, c, d, e, f) && (segment_crosses_triangle(d, e, a, b, c) ||
                                         segment_crosses_triangle(e, f, a, b, c) ||
                                         segment_crosses_triangle(f, d, a, b, c));
}

}  // namespace

namespace {

// Uniform grid over the boxes of a set of faces (flat boxes: lo xyz, hi xyz per face):
// cells about as large as a face, each face listed in every cell its box overlaps.
struct Grid {
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, inv = 1;
  int n[3] = {1, 1, 1};
  std::vector<int> start, items;
  std::vector<int> low;  // per face of the box list: the cell of its box's low corner (listed faces only)

  int coord(double x, int d) const {
    const double t = std::floor((x - lo[d]) * inv);
    return t < 0 ? 0 : (t >= n[d] ? n[d] - 1 : static_cast<int>(t));
  }
  void range(const double* b, int r[6]) const {
    for (int d = 0; d < 3; ++d) {
      r[d] = coord(b[d], d);
      r[3 + d] = coord(b[3 + d], d);
    }
  }
  size_t cell(int x, int y, int z) const { return (static_cast<size_t>(z) * n[1] + y) * n[0] + x; }
  bool outside(const double* b) const {
    return b[0] > hi[0] || b[1] > hi[1] || b[2] > hi[2] || b[3] < lo[0] || b[4] < lo[1] || b[5] < lo[2];
  }

  void build(const std::vector<double>& box, const std::vector<int>& faces) {
    const int m = static_cast<int>(faces.size());
    double ext = 0;
    for (int d = 0; d < 3; ++d) {
      lo[d] = box[6 * static_cast<size_t>(faces[0]) + d];
      hi[d] = box[6 * static_cast<size_t>(faces[0]) + 3 + d];
    }
    for (int f : faces) {
      const double* x = &box[6 * static_cast<size_t>(f)];
      double e = 0;
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::min(lo[d], x[d]);
        hi[d] = std::max(hi[d], x[3 + d]);
        e = std::max(e, x[3 + d] - x[d]);
      }
      ext += e;
    }
    for (int d = 0; d < 3; ++d)
      require(std::isfinite(lo[d]) && std::isfinite(hi[d]), "self_intersections: non-finite vertex coordinates");
    double c = std::max(ext / m, 1e-300);
    const long long max_cells = std::max<long long>(4LL * m, 1 << 12);
    const auto cells_for = [&](double cs) {
      long long total = 1;
      for (int d = 0; d < 3; ++d) total *= std::max<long long>(1, static_cast<long long>((hi[d] - lo[d]) / cs) + 1);
      return total;
    };
    while (cells_for(c) > max_cells) c *= 1.25;
    inv = 1.0 / c;
    for (int d = 0; d < 3; ++d) n[d] = static_cast<int>(std::max<long long>(1, static_cast<long long>((hi[d] - lo[d]) / c) + 1));
    const size_t nc = static_cast<size_t>(n[0]) * n[1] * n[2];
    start.assign(nc + 1, 0);
    for (int f : faces) {
      int r[6];
      range(&box[6 * static_cast<size_t>(f)], r);
      for (int z = r[2]; z <= r[5]; ++z)
        for (int y = r[1]; y <= r[4]; ++y)
          for (int x = r[0]; x <= r[3]; ++x) ++start[cell(x, y, z) + 1];
    }
    for (size_t q = 0; q < nc; ++q) start[q + 1] += start[q];
    items.resize(start[nc]);
    std::vector<int> pos(start.begin(), start.end() - 1);
    low.assign(box.size() / 2, 0);
    for (int f : faces) {
      int r[6];
      range(&box[6 * static_cast<size_t>(f)], r);
      for (int d = 0; d < 3; ++d) low[3 * static_cast<size_t>(f) + d] = r[d];
      for (int z = r[2]; z <= r[5]; ++z)
        for (int y = r[1]; y <= r[4]; ++y)
          for (int x = r[0]; x <= r[3]; ++x) items[pos[cell(x, y, z)]++] = f;
    }
  }

  // Calls visit(g) for every listed face g whose box overlaps box b, once per g: in the
  // cell holding the low corner of the two boxes' intersection (coord is monotone: that
  // cell is the larger of the two boxes' low cells, compared in integers first).
  template <class Visit>
  void overlapping(const std::vector<double>& box, const double* b, Visit&& visit) const {
    int r[6];
    range(b, r);
    for (int z = r[2]; z <= r[5]; ++z)
      for (int y = r[1]; y <= r[4]; ++y)
        for (int x = r[0]; x <= r[3]; ++x) {
          const size_t c = cell(x, y, z);
          for (int q = start[c]; q < start[c + 1]; ++q) {
            const int g = items[q];
            const int* lg = &low[3 * static_cast<size_t>(g)];
            if (std::max(r[0], lg[0]) != x || std::max(r[1], lg[1]) != y || std::max(r[2], lg[2]) != z) continue;
            const double* bg = &box[6 * static_cast<size_t>(g)];
            if (bg[0] > b[3] || b[0] > bg[3] || bg[1] > b[4] || b[1] > bg[4] || bg[2] > b[5] || b[2] > bg[5]) continue;
            visit(g);
          }
        }
  }
};

}  // namespace

namespace {

// The box (lo xyz, hi xyz) of triangle t over the vertex positions of V.
inline void triangle_box(const std::vector<Eigen::Vector3d>& V, const Eigen::Vector3i& t, double* x) {
  for (int d = 0; d < 3; ++d) {
    x[d] = std::min({V[t[0]][d], V[t[1]][d], V[t[2]][d]});
    x[3 + d] = std::max({V[t[0]][d], V[t[1]][d], V[t[2]][d]});
  }
}

// Boxes (lo xyz, hi xyz per face) of the faces over the vertex positions of V and, when
// given, of V1 as well.
std::vector<double> face_boxes(const std::vector<Eigen::Vector3d>& V, const std::vector<Eigen::Vector3i>& F,
                               const std::vector<Eigen::Vector3d>* V1 = nullptr) {
  const int nf = static_cast<int>(F.size());
  std::vector<double> box(6 * static_cast<size_t>(nf));
#pragma omp parallel for schedule(static)
  for (int f = 0; f < nf; ++f) {
    double* x = &box[6 * static_cast<size_t>(f)];
    triangle_box(V, F[f], x);
    for (int d = 0; d < 3; ++d) {
      if (V1) {
        const auto& W = *V1;
        x[d] = std::min({x[d], W[F[f][0]][d], W[F[f][1]][d], W[F[f][2]][d]});
        x[3 + d] = std::max({x[3 + d], W[F[f][0]][d], W[F[f][1]][d], W[F[f][2]][d]});
      }
    }
  }
  return box;
}

// Results per fixed chunk of n items, concatenated in order: deterministic.
template <class Body>
void run_chunks(int n, std::vector<std::pair<int, int>>& out, Body&& body) {
  constexpr int kChunk = 2048;
  const int nchunks = (n + kChunk - 1) / kChunk;
  std::vector<std::vector<std::pair<int, int>>> found(nchunks);
#pragma omp parallel for schedule(dynamic, 1)
  for (int ch = 0; ch < nchunks; ++ch)
    for (int i = ch * kChunk; i < std::min(n, (ch + 1) * kChunk); ++i) body(i, found[ch]);
  size_t total = out.size();
  for (const auto& v : found) total += v.size();
  out.reserve(total);
  for (const auto& v : found) out.insert(out.end(), v.begin(), v.end());
}

}  // namespace

MotionPairs::MotionPairs(const std::vector<Eigen::Vector3d>& V0, const std::vector<Eigen::Vector3d>& V1,
                         const std::vector<Eigen::Vector3i>& F)
    : F_(F) {
  require(V0.size() == V1.size(), "MotionPairs: ", V0.size(), " start and ", V1.size(), " end positions");
  const int nf = static_cast<int>(F.size());
  if (nf < 2) return;
  const std::vector<double> box = face_boxes(V0, F, &V1);
  std::vector<int> all(nf);
  std::iota(all.begin(), all.end(), 0);
  Grid grid;
  grid.build(box, all);
  run_chunks(nf, pairs_, [&](int f, std::vector<std::pair<int, int>>& found) {
    grid.overlapping(box, &box[6 * static_cast<size_t>(f)], [&](int g) {
      int ti, ui;
      if (g > f && shared_count(F[f], F[g], ti, ui) < 2) found.emplace_back(f, g);
    });
  });
  std::sort(pairs_.begin(), pairs_.end());
}

std::vector<std::pair<int, int>> MotionPairs::intersections(const std::vector<Eigen::Vector3d>& V,
                                                            const std::vector<char>& only_faces) const {
  const bool filter = !only_faces.empty();
  require(!filter || only_faces.size() == F_.size(), "MotionPairs::intersections: ", only_faces.size(),
          " face flags for ", F_.size(), " faces");
  std::vector<std::pair<int, int>> out;
  run_chunks(static_cast<int>(pairs_.size()), out, [&](int k, std::vector<std::pair<int, int>>& found) {
    const auto& p = pairs_[k];
    if (filter && !only_faces[p.first] && !only_faces[p.second]) return;
    if (triangles_cross(V, F_[p.first], F_[p.second])) found.push_back(p);
  });
  return out;  // in the order of the sorted list
}

std::vector<std::pair<int, int>> self_intersections(const std::vector<Eigen::Vector3d>& V,
                                                    const std::vector<Eigen::Vector3i>& F,
                                                    const std::vector<char>& only_faces) {
  const int nf = static_cast<int>(F.size());
  std::vector<std::pair<int, int>> out;
  if (nf < 2) return out;
  const bool filter = !only_faces.empty();
  std::vector<int> query;
  if (filter) {
    for (int f = 0; f < nf; ++f)
      if (only_faces[f]) query.push_back(f);
    if (query.empty()) return out;
  }
  Grid grid;
  if (filter && static_cast<long long>(query.size()) * 8 < nf) {
    // Few listed faces: their boxes and a grid of them only (numbered 0..nq-1), every
    // face's box made on the fly and looked up in it (no array over all faces: deform's
    // untangling asks this many times an iteration for a few faces of a mesh of millions).
    // A pair of two listed faces is tested from its lower face.
    const int nq = static_cast<int>(query.size());
    std::vector<double> qbox(6 * static_cast<size_t>(nq));
    for (int k = 0; k < nq; ++k) triangle_box(V, F[query[k]], &qbox[6 * static_cast<size_t>(k)]);
    std::vector<int> local(nq);
    std::iota(local.begin(), local.end(), 0);
    grid.build(qbox, local);
    run_chunks(nf, out, [&](int s, std::vector<std::pair<int, int>>& found) {
      double bs[6];
      triangle_box(V, F[s], bs);
      if (grid.outside(bs)) return;
      grid.overlapping(qbox, bs, [&](int k) {
        const int f = query[k];
        if (f == s || (only_faces[s] && s < f)) return;
        if (triangles_cross(V, F[f], F[s])) found.emplace_back(std::min(f, s), std::max(f, s));
      });
    });
  } else {
    // A grid of every face; the listed faces (all when unfiltered) are looked up in it.
    const std::vector<double> box = face_boxes(V, F);
    std::vector<int> all(nf);
    std::iota(all.begin(), all.end(), 0);
    grid.build(box, all);
    const int nq = filter ? static_cast<int>(query.size()) : nf;
    run_chunks(nq, out, [&](int qi, std::vector<std::pair<int, int>>& found) {
      const int f = filter ? query[qi] : qi;
      grid.overlapping(box, &box[6 * static_cast<size_t>(f)], [&](int g) {
        if (g == f || (filter ? (only_faces[g] && g < f) : g < f)) return;
        if (triangles_cross(V, F[f], F[g])) found.emplace_back(std::min(f, g), std::max(f, g));
      });
    });
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace tetmvs::deform
