// Point location and ray walk against brute force, including degenerate rays (through
// vertices, along edges and faces) and rays through the ghost pyramids at the boundary.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "common/tetmesh/locate.h"
#include "common/tetmesh/refine.h"
#include "tests/unit/sanitized.h"

using namespace tetmvs::tet;

namespace {

// An adaptive mesh: 3 levels refined around an off-centre point, with green cells.
const TetMesh& adaptive_mesh() {
  static const TetMesh mesh = [] {
    Lattice lat;
    lat.origin = Eigen::Vector3d(0.5, -1.0, 2.0);
    lat.h = 0.5;
    lat.dims = {4, 3, 3};
    TetMesh m = build_bcc(lat);
    const Eigen::Vector3d p = lat.grid_box().center() + Eigen::Vector3d(0.21, -0.1, 0.13);
    for (int l = 0; l < 3; ++l) {
      std::vector<std::uint8_t> act(m.num_cells(), 0);
      for (std::int32_t c = 0; c < m.num_cells(); ++c) act[c] = (m.cell_centroid(c) - p).norm() < 0.45;
      // and the whole boundary layer on one side, to refine boundary faces
      for (std::int32_t c = 0; c < m.num_cells(); ++c)
        if (l == 0 && m.cell_centroid(c).x() < lat.origin.x() + 0.4) act[c] = 1;
      m = refine(m, act);
    }
    return m;
  }();
  return mesh;
}

std::int32_t brute_locate(const TetMesh& m, const I3& P) {
  std::int32_t found = -1;
  int count = 0;
  for (std::int32_t c = 0; c < m.num_cells(); ++c)
    if (cell_contains(m, c, P, kSoS1)) found = c, ++count;
  EXPECT_LE(count, 1);
  return found;
}

// Segment a + t(b-a) inside cell c (closed): [lo, hi], empty when lo > hi.
std::pair<double, double> clip(const TetMesh& m, std::int32_t c, const Eigen::Vector3d& a,
                               const Eigen::Vector3d& b) {
  double lo = 0, hi = 1;
  const Tet& t = m.cell_v[c];
  for (int j = 0; j < 4; ++j) {
    const Eigen::Vector3d x0 = m.vertex(t[kFace[j][0]]), x1 = m.vertex(t[kFace[j][1]]),
                          x2 = m.vertex(t[kFace[j][2]]);
    const Eigen::Vector3d n = (x1 - x0).cross(x2 - x0).normalized();
    const double s0 = n.dot(a - x0), ds = n.dot(b - a);  // inside: s0 + t ds <= 0
    if (std::abs(ds) < 1e-15) {
      if (s0 > 1e-12) return {1, 0};
      continue;
    }
    const double t0 = -s0 / ds;
    if (ds > 0) hi = std::min(hi, t0);
    else lo = std::max(lo, t0);
  }
  return {lo, hi};
}

void check_walk(const TetMesh& m, const Eigen::Vector3d& a, const Eigen::Vector3d& b, bool generic) {
  std::vector<WalkHit> w;
  walk_segment(m, a, b, w);
  const double L = (b - a).norm();
  const double tol = 1e-9 / std::max(L, 1e-3);
  std::set<std::int32_t> seen;
  double walked = 0;
  for (std::size_t k = 0; k < w.size(); ++k) {
    const WalkHit& h = w[k];
    ASSERT_TRUE(seen.insert(h.cell).second) << "cell visited twice";
    ASSERT_LE(h.t_in, h.t_out);
    walked += h.t_out - h.t_in;
    const auto [lo, hi] = clip(m, h.cell, a, b);
    ASSERT_GE(hi - lo, -tol) << "walk visits a cell the segment does not touch";
    // (a segment lying in a face may cross it anywhere under the perturbation)
    if (generic && hi - lo > tol) {
      EXPECT_NEAR(h.t_in, lo, 1e-7);
      EXPECT_NEAR(h.t_out, hi, 1e-7);
    }
    if (k + 1 < w.size()) {
      ASSERT_LE(h.t_out, w[k + 1].t_in + 1e-12);
      if (h.face_out >= 0 && !m.face_on_boundary(h.face_out)) {
        ASSERT_EQ(h.face_out, w[k + 1].face_in);
      } else {
        ASSERT_GE(h.face_out, 0);
        ASSERT_TRUE(m.face_on_boundary(w[k + 1].face_in));
      }
    }
    if (h.face_in >= 0) {
      const std::int32_t f = h.face_in;
      ASSERT_TRUE(m.face_cell(f, 0) == h.cell || m.face_cell(f, 1) == h.cell);
    }
  }
  double total = 0;
  std::int32_t must = 0;
  std::vector<std::pair<double, double>> spans;
  for (std::int32_t c = 0; c < m.num_cells(); ++c) {
    const auto [lo, hi] = clip(m, c, a, b);
    if (hi - lo <= 0) continue;
    spans.emplace_back(lo, hi);
    total += hi - lo;
    if (generic && hi - lo > 1e-7) {
      ++must;
      EXPECT_TRUE(seen.count(c)) << "walk misses cell " << c << " (length " << hi - lo << ")";
    }
  }
  // the walk covers exactly the part of the segment inside the mesh (the union of the
  // brute-force intervals; along a face or edge several cells share a part)
  std::sort(spans.begin(), spans.end());
  double covered = 0, end = -1e30;
  for (const auto& [lo, hi] : spans) {
    if (hi <= end) continue;
    covered += hi - std::max(lo, end);
    end = hi;
  }
  EXPECT_NEAR(walked, covered, 1e-7);
  if (generic) {
    EXPECT_NEAR(walked, total, 1e-7);
  }
}

}  // namespace

TEST(TetMeshLocate, AgreesWithBruteForce) {
  const TetMesh& m = adaptive_mesh();
  ASSERT_GT(m.max_cell_level(), 2);
  std::mt19937 rng(3);
  const auto box = m.lat.grid_box();
  std::uniform_real_distribution<double> U(0, 1);
  int inside = 0, ghost = 0;
  for (int i = 0; i < 1500; ++i) {
    const Eigen::Vector3d x = box.min() + box.sizes().cwiseProduct(Eigen::Vector3d(U(rng), U(rng), U(rng)));
    const I3 P = m.lat.to_fixed(x);
    const std::int32_t c = locate_fixed(m, P);
    ASSERT_EQ(c, brute_locate(m, P)) << "point " << x.transpose();
    ASSERT_EQ(c, locate(m, x));
    (c >= 0 ? inside : ghost)++;
  }
  EXPECT_GT(ghost, 0);
  EXPECT_GT(inside, 1000);
  // exactly on vertices, edge midpoints and face centroids (all degenerate)
  for (int i = 0; i < 600; ++i) {
    const std::int32_t c = static_cast<std::int32_t>(rng() % m.num_cells());
    const Tet& t = m.cell_v[c];
    I3 P;
    if (i % 3 == 0) P = m.vfixed(t[rng() % 4]);
    else if (i % 3 == 1) {
      const int k = rng() % 6;
      const I3 a = m.vfixed(t[kEdge[k][0]]), b = m.vfixed(t[kEdge[k][1]]);
      P = {(a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2};
    } else {
      const int j = rng() % 4;
      const I3 a = m.vfixed(t[kFace[j][0]]), b = m.vfixed(t[kFace[j][1]]), d = m.vfixed(t[kFace[j][2]]);
      P = {(a.x + b.x + d.x) / 3, (a.y + b.y + d.y) / 3, (a.z + b.z + d.z) / 3};
    }
    ASSERT_EQ(locate_fixed(m, P), brute_locate(m, P));
  }
  EXPECT_EQ(locate(m, box.max() + Eigen::Vector3d(1, 0, 0)), -1);
}

TEST(TetMeshWalk, RandomSegmentsAgreeWithBruteForce) {
  const TetMesh& m = adaptive_mesh();
  std::mt19937 rng(5);
  const auto box = m.lat.grid_box();
  std::uniform_real_distribution<double> U(-0.2, 1.2);
  for (int i = 0; i < tetmvs::test::reps(400, 100); ++i) {
    const Eigen::Vector3d a = box.min() + box.sizes().cwiseProduct(Eigen::Vector3d(U(rng), U(rng), U(rng)));
    const Eigen::Vector3d b = box.min() + box.sizes().cwiseProduct(Eigen::Vector3d(U(rng), U(rng), U(rng)));
    SCOPED_TRACE(i);
    check_walk(m, a, b, true);
  }
}

TEST(TetMeshWalk, DegenerateSegments) {
  // Kept 0.6 h inside the grid box: a segment lying on the jagged domain boundary may
  // be perturbed to either side of it (the random test covers the boundary).
  const TetMesh& m = adaptive_mesh();
  std::mt19937 rng(9);
  const std::int32_t NV = m.num_vertices();
  Eigen::AlignedBox3d inner = m.lat.grid_box();
  inner.min().array() += 0.6 * m.lat.h;
  inner.max().array() -= 0.6 * m.lat.h;
  int through = 0;
  const int n = tetmvs::test::reps(400, 100);
  for (int i = 0; i < n; ++i) {
    SCOPED_TRACE(i);
    // vertex to vertex (through vertices, often along edges or faces of the lattice)
    const Eigen::Vector3d a = m.vertex(rng() % NV), b = m.vertex(rng() % NV);
    if ((a - b).norm() > 0 && inner.contains(a) && inner.contains(b)) check_walk(m, a, b, false), ++through;
    // along lattice axes and diagonals through a vertex, across the inner box
    static const double dirs[7][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, {1, -1, 1}, {1, 1, 0}, {0, 1, -1}};
    const auto& d = dirs[i % 7];
    const Eigen::Vector3d dir(d[0], d[1], d[2]);
    const Eigen::Vector3d c = m.vertex(rng() % NV);
    if (!inner.contains(c)) continue;
    double t0 = -1e9, t1 = 1e9;
    for (int k = 0; k < 3; ++k) {
      if (dir[k] == 0) continue;
      double u = (inner.min()[k] - c[k]) / dir[k], w = (inner.max()[k] - c[k]) / dir[k];
      if (u > w) std::swap(u, w);
      t0 = std::max(t0, u), t1 = std::min(t1, w);
    }
    check_walk(m, c + t0 * dir, c + t1 * dir, false);
    ++through;
  }
  EXPECT_GT(through, 3 * n / 4);
}

TEST(TetMeshWalk, RaysLeaveTheBox) {
  const TetMesh& m = adaptive_mesh();
  std::mt19937 rng(2);
  std::normal_distribution<double> N(0, 1);
  std::vector<WalkHit> w;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d o = m.lat.grid_box().center();
    const Eigen::Vector3d dir = Eigen::Vector3d(N(rng), N(rng), N(rng)).normalized();
    walk_ray(m, o, dir, w);
    ASSERT_FALSE(w.empty());
    EXPECT_EQ(w.front().cell, locate(m, o));
    EXPECT_EQ(w.front().face_in, -1);
    EXPECT_GE(w.back().face_out, 0);
    EXPECT_TRUE(m.face_on_boundary(w.back().face_out));
    // the last exit is within h/2 of the grid box surface
    const Eigen::Vector3d x = o + w.back().t_out * dir;
    const auto box = m.lat.grid_box();
    const double dist = std::min((x - box.min()).minCoeff(), (box.max() - x).minCoeff());
    EXPECT_LE(dist, 0.5 * m.lat.h + 1e-9);
  }
}
