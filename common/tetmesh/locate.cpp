// Point location through the hierarchy and the exact ray walk (see locate.h).
#include "common/tetmesh/locate.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.h"

namespace tetmvs::tet {
namespace {

// Square corners (offsets along b, c) in quadrant order, closed.
constexpr int kCorner[5][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};

struct Grid {
  std::int64_t CS;  // cube edge in fixed-point units
  int n[3];
  std::int32_t base[3];
  explicit Grid(const Lattice& lat) : CS(lat.cube_fixed()) {
    for (int a = 0; a < 3; ++a) n[a] = lat.dims[a];
    base[0] = 0;
    base[1] = 4 * (n[0] - 1) * n[1] * n[2];
    base[2] = base[1] + 4 * n[0] * (n[1] - 1) * n[2];
  }
  std::int32_t l0_id(int a, int fa, int ib, int ic, int q) const {
    const int b = (a + 1) % 3;
    return base[a] + 4 * ((fa - 1) + (n[a] - 1) * (ib + n[b] * ic)) + q;
  }
  struct L0 {
    int a, fa, ib, ic, q;
  };
  L0 l0_decode(std::int32_t r) const {
    int a = r >= base[2] ? 2 : r >= base[1] ? 1 : 0;
    const int b = (a + 1) % 3;
    const std::int32_t local = r - base[a];
    const int q = local & 3;
    std::int32_t idx = local >> 2;
    const int fa = idx % (n[a] - 1) + 1;
    idx /= (n[a] - 1);
    return {a, fa, static_cast<int>(idx % n[b]), static_cast<int>(idx / n[b]), q};
  }
  std::int32_t ghost_id(const int cube[3], int axis, int side) const {
    return ((std::int32_t(cube[2]) * n[1] + cube[1]) * n[0] + cube[0]) * 6 + 2 * axis + side;
  }
  void ghost_decode(std::int32_t g, int cube[3], int& axis, int& side) const {
    const int k = g % 6;
    axis = k >> 1, side = k & 1;
    std::int32_t c = g / 6;
    cube[0] = c % n[0];
    c /= n[0];
    cube[1] = c % n[1];
    cube[2] = c / n[1];
  }
  I3 corner(int i, int j, int k) const { return {i * CS, j * CS, k * CS}; }
  I3 centre(const int c[3]) const {
    return {c[0] * CS + CS / 2, c[1] * CS + CS / 2, c[2] * CS + CS / 2};
  }
};

inline I3 vfix(const TetMesh& m, std::int32_t v) { return m.vfixed(v); }

inline bool tet_contains(const TetMesh& m, const Tet& t, const I3& P, const I3& v) {
  const I3 V[4] = {vfix(m, t[0]), vfix(m, t[1]), vfix(m, t[2]), vfix(m, t[3])};
  for (int j = 0; j < 4; ++j)
    if (orient_sos(V[kFace[j][0]], V[kFace[j][1]], V[kFace[j][2]], P, v) > 0) return false;
  return true;
}

// |d + e*v| compared lexicographically as (|d|, sgn*v).
struct SosAbs {
  std::int64_t mag, slope;
  bool operator>(const SosAbs& o) const { return mag != o.mag ? mag > o.mag : slope > o.slope; }
};
inline int sos_sign(std::int64_t d, std::int64_t v) { return d != 0 ? (d > 0 ? 1 : -1) : (v > 0 ? 1 : -1); }
inline SosAbs sos_abs(std::int64_t d, std::int64_t v) {
  const int s = sos_sign(d, v);
  return {d < 0 ? -d : d, s * v};
}

inline std::int64_t comp(const I3& p, int a) { return a == 0 ? p.x : a == 1 ? p.y : p.z; }
inline void set_comp(I3& p, int a, std::int64_t v) { (a == 0 ? p.x : a == 1 ? p.y : p.z) = v; }

// Level-0 tet holding P + e*v: its node id, or -1 with *ghost set (or -1 outside the box).
std::int32_t locate_level0(const Grid& g, const I3& P, const I3& v, std::int32_t* ghost) {
  if (ghost) *ghost = -1;
  int cube[3];
  std::int64_t d[3], vv[3];
  for (int a = 0; a < 3; ++a) {
    const std::int64_t x = comp(P, a);
    vv[a] = comp(v, a);
    std::int64_t i = x >= 0 ? x / g.CS : -((-x + g.CS - 1) / g.CS);
    if (x == i * g.CS && vv[a] < 0) --i;
    if (i < 0 || i >= g.n[a]) return -1;
    cube[a] = static_cast<int>(i);
    d[a] = x - (i * g.CS + g.CS / 2);
  }
  int a = 0;
  SosAbs best = sos_abs(d[0], vv[0]);
  for (int k = 1; k < 3; ++k) {
    const SosAbs s = sos_abs(d[k], vv[k]);
    if (s > best) best = s, a = k;
  }
  const int side = sos_sign(d[a], vv[a]) > 0 ? 1 : 0;
  const int fa = cube[a] + side;
  if (fa == 0 || fa == g.n[a]) {
    if (ghost) *ghost = g.ghost_id(cube, a, side);
    return -1;
  }
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  int q;
  if (sos_abs(d[c], vv[c]) > sos_abs(d[b], vv[b]))
    q = sos_sign(d[c], vv[c]) < 0 ? 0 : 2;
  else
    q = sos_sign(d[b], vv[b]) > 0 ? 1 : 3;
  return g.l0_id(a, fa, cube[b], cube[c], q);
}

std::int32_t descend(const TetMesh& m, std::int32_t node, const I3& P, const I3& v) {
  while (m.node_child[node] >= 0) {
    const std::int32_t ch = m.node_child[node];
    std::int32_t next = -1;
    for (int k = 0; k < 8 && next < 0; ++k)
      if (tet_contains(m, m.node_v[ch + k], P, v)) next = ch + k;
    if (next < 0) fail("locate: internal error, no child of node ", node, " holds the point");
    node = next;
  }
  const std::int32_t c0 = m.node_cell[node], nc = m.node_ncell[node];
  if (nc == 1) return c0;
  for (std::int32_t c = c0; c < c0 + nc; ++c)
    if (tet_contains(m, m.cell_v[c], P, v)) return c;
  fail("locate: internal error, no green cell of node ", node, " holds the point");
}

}  // namespace

bool cell_contains(const TetMesh& m, std::int32_t c, const I3& P, const I3& v) {
  return tet_contains(m, m.cell_v[c], P, v);
}

std::int32_t locate_fixed(const TetMesh& m, const I3& P, const I3& v, std::int32_t* ghost) {
  const Grid g(m.lat);
  const std::int32_t r = locate_level0(g, P, v, ghost);
  if (r < 0) return -1;
  return descend(m, r, P, v);
}

std::int32_t locate(const TetMesh& m, const Eigen::Vector3d& x) {
  const Eigen::Vector3d l = m.lat.to_lattice(x);
  const double lim = static_cast<double>(m.lat.cube_fixed() >> kFixedBits);
  for (int a = 0; a < 3; ++a)
    if (!(l[a] >= 0 && l[a] <= lim * m.lat.dims[a])) return -1;
  return locate_fixed(m, m.lat.to_fixed(x));
}

// ---------------------------------------------------------------------------------------
// The walk.
namespace {

struct Walker {
  const TetMesh& m;
  const Grid g;
  Line L;
  Eigen::Vector3d a, ab;  // world segment a + t*ab
  double t_end;
  std::vector<WalkHit>& out;
  double t_stop = std::numeric_limits<double>::infinity();  // no cell entered beyond this is reported
  // the segment in lattice-double units (for param)
  Eigen::Vector3d A = m.lat.to_lattice(a), D = ab / m.lat.unit();

  double param(const I3& x0, const I3& x1, const I3& x2, double tmin) const {
    // plane of three fixed-point points against the world segment, in lattice-double units
    constexpr double s = 1.0 / static_cast<double>(std::int64_t{1} << kFixedBits);
    const Eigen::Vector3d p0(x0.x * s, x0.y * s, x0.z * s), p1(x1.x * s, x1.y * s, x1.z * s),
        p2(x2.x * s, x2.y * s, x2.z * s);
    const Eigen::Vector3d n = (p1 - p0).cross(p2 - p0);
    const double den = n.dot(D);
    double t = tmin;
    if (den != 0.0) t = n.dot(p0 - A) / den;
    if (!(t >= tmin)) t = tmin;
    if (t > t_end) t = t_end;
    return t;
  }

  // Cell c entered through local face jin (-1: start inside). Returns the local exit face.
  int exit_face(std::int32_t c, int jin, const I3 V[4]) const {
    std::int8_t es[6] = {0, 0, 0, 0, 0, 0};
    if (jin >= 0)
      for (int e = 0; e < 3; ++e) {
        const int x = kFace[jin][e], y = kFace[jin][(e + 1) % 3];
        es[kEdgeIndex[x][y]] = static_cast<std::int8_t>(x < y ? -1 : 1);
      }
    auto side = [&](int x, int y) -> int {
      const int k = kEdgeIndex[x][y];
      if (!es[k]) es[k] = static_cast<std::int8_t>(line_side(L, V[kEdge[k][0]], V[kEdge[k][1]]));
      return x < y ? es[k] : -es[k];
    };
    for (int j = 0; j < 4; ++j) {
      if (j == jin) continue;
      const int x = kFace[j][0], y = kFace[j][1], z = kFace[j][2];
      if (side(x, y) < 0 || side(y, z) < 0 || side(z, x) < 0) continue;
      return j;
    }
    fail("walk: internal error, no exit face in cell ", c);
  }

  // The boundary face j of cell c lies on a side of this ghost pyramid.
  std::int32_t ghost_of_boundary(std::int32_t c, int j) const {
    std::int32_t r = m.cell_node[c];
    while (r >= m.num_level0) r = m.node_parent[r];
    const auto d = g.l0_decode(r);
    const int b = (d.a + 1) % 3, cc = (d.a + 2) % 3;
    int lo[3], hi[3];
    lo[d.a] = d.fa - 1, hi[d.a] = d.fa;
    lo[b] = hi[b] = d.ib;
    lo[cc] = hi[cc] = d.ic;
    I3 A[2];
    for (int s = 0; s < 2; ++s) {
      I3 p;
      set_comp(p, d.a, d.fa * g.CS);
      set_comp(p, b, (d.ib + kCorner[d.q + s][0]) * g.CS);
      set_comp(p, cc, (d.ic + kCorner[d.q + s][1]) * g.CS);
      A[s] = p;
    }
    const Tet& t = m.cell_v[c];
    const I3 F[3] = {vfix(m, t[kFace[j][0]]), vfix(m, t[kFace[j][1]]), vfix(m, t[kFace[j][2]])};
    const int* cube = nullptr;
    for (const int* cand : {lo, hi}) {
      const I3 C = g.centre(cand);
      if (orient_sign(C, A[0], A[1], F[0]) == 0 && orient_sign(C, A[0], A[1], F[1]) == 0 &&
          orient_sign(C, A[0], A[1], F[2]) == 0)
        cube = cand;
    }
    if (!cube) fail("walk: internal error, boundary face of cell ", c, " is not on a ghost pyramid");
    static const int oax[4] = {2, 1, 2, 1};  // 2: axis c of the square, 1: axis b
    static const int osd[4] = {0, 1, 1, 0};
    const int o = oax[d.q] == 2 ? cc : b;
    const int so = osd[d.q];
    if (cube[o] + so != 0 && cube[o] + so != g.n[o])
      fail("walk: internal error, boundary face of cell ", c, " is inside the grid");
    return g.ghost_id(cube, o, so);
  }

  // Enter level-0 tet r through its face triangle T (three fixed points): the leaf cell
  // and local face the line enters through.
  std::pair<std::int32_t, int> enter(std::int32_t node, const I3 T[3]) const {
    auto entering = [&](const Tet& t, int& jout) {
      const I3 V[4] = {vfix(m, t[0]), vfix(m, t[1]), vfix(m, t[2]), vfix(m, t[3])};
      for (int j = 0; j < 4; ++j) {
        const I3& x = V[kFace[j][0]];
        const I3& y = V[kFace[j][1]];
        const I3& z = V[kFace[j][2]];
        if (orient_sign(T[0], T[1], T[2], x) != 0 || orient_sign(T[0], T[1], T[2], y) != 0 ||
            orient_sign(T[0], T[1], T[2], z) != 0)
          continue;
        if (line_side(L, x, y) < 0 && line_side(L, y, z) < 0 && line_side(L, z, x) < 0) {
          jout = j;
          return true;
        }
        return false;  // a tet has at most one face in the plane
      }
      return false;
    };
    int j = -1;
    while (m.node_child[node] >= 0) {
      const std::int32_t ch = m.node_child[node];
      std::int32_t next = -1;
      for (int k = 0; k < 8 && next < 0; ++k)
        if (entering(m.node_v[ch + k], j)) next = ch + k;
      if (next < 0) fail("walk: internal error, no child of node ", node, " is entered");
      node = next;
    }
    const std::int32_t c0 = m.node_cell[node], nc = m.node_ncell[node];
    for (std::int32_t c = c0; c < c0 + nc; ++c)
      if (entering(m.cell_v[c], j)) return {c, j};
    fail("walk: internal error, no cell of node ", node, " is entered");
  }

  // Crosses ghost pyramid gh; returns the cell and local face entered, or {-1,-1} when the
  // segment ends inside the pyramid or leaves the grid box.
  std::pair<std::int32_t, int> cross_ghost(std::int32_t gh) const {
    for (int guard = 0; guard < 16; ++guard) {
      int cube[3], a, side;
      g.ghost_decode(gh, cube, a, side);
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      const I3 apex = g.centre(cube);
      I3 s[4];
      for (int k = 0; k < 4; ++k) {
        I3 p;
        set_comp(p, a, (cube[a] + side) * g.CS);
        set_comp(p, b, (cube[b] + kCorner[k][0]) * g.CS);
        set_comp(p, c, (cube[c] + kCorner[k][1]) * g.CS);
        s[k] = p;
      }
      // an interior point, for orienting the faces outward
      const I3 bc = {(s[0].x + s[2].x) / 2, (s[0].y + s[2].y) / 2, (s[0].z + s[2].z) / 2};
      const I3 in = {(3 * apex.x + bc.x) / 4, (3 * apex.y + bc.y) / 4, (3 * apex.z + bc.z) / 4};
      I3 tri[6][3] = {{apex, s[0], s[1]}, {apex, s[1], s[2]}, {apex, s[2], s[3]},
                      {apex, s[3], s[0]}, {s[0], s[1], s[2]}, {s[0], s[2], s[3]}};
      int exit = -1;
      for (int f = 0; f < 6 && exit < 0; ++f) {
        if (orient_sign(tri[f][0], tri[f][1], tri[f][2], in) > 0) std::swap(tri[f][1], tri[f][2]);
        if (line_side(L, tri[f][0], tri[f][1]) > 0 && line_side(L, tri[f][1], tri[f][2]) > 0 &&
            line_side(L, tri[f][2], tri[f][0]) > 0)
          exit = f;
      }
      if (exit < 0) fail("walk: internal error, no exit from a ghost pyramid");
      if (orient_sos(tri[exit][0], tri[exit][1], tri[exit][2], L.Q, kSoS2) < 0) return {-1, -1};
      if (exit >= 4) return {-1, -1};  // leaves the grid box
      static const int oax[4] = {2, 1, 2, 1};
      static const int osd[4] = {0, 1, 1, 0};
      const int o = oax[exit] == 2 ? c : b;
      const int so = osd[exit];
      const int fo = cube[o] + so;
      if (fo == 0 || fo == g.n[o]) {
        gh = g.ghost_id(cube, o, so);
        continue;
      }
      // the bipyramid across face (o, fo): its tet with A edge (s[exit], s[exit+1])
      const int e = exit % 2 == 0 ? b : c;  // axis of the A edge
      const int bo = (o + 1) % 3, co = (o + 2) % 3;
      int q;
      if (e == bo)
        q = side == 0 ? 0 : 2;
      else
        q = side == 0 ? 3 : 1;
      const std::int32_t r = g.l0_id(o, fo, cube[bo], cube[co], q);
      const I3 T[3] = {apex, s[exit], s[(exit + 1) % 4]};
      return enter(r, T);
    }
    fail("walk: internal error, too many ghost pyramids in a row");
  }

  void run(double t0, std::int32_t* start) {
    std::int32_t gh = -1;
    // the start point's cell: the hint or one of its neighbours when one holds it (the
    // containing cell is unique, so this is locate's answer), else located
    std::int32_t c = -1;
    if (start && *start >= 0) {
      if (cell_contains(m, *start, L.P)) c = *start;
      for (int j = 0; j < 4 && c < 0; ++j) {
        const std::int32_t nb = m.neighbour(*start, j);
        if (nb >= 0 && cell_contains(m, nb, L.P)) c = nb;
      }
    }
    if (c < 0) c = locate_fixed(m, L.P, kSoS1, &gh);
    if (start) *start = c;
    int jin = -1;
    std::int32_t face_in = -1;
    double t_in = t0;
    if (c < 0) {
      if (gh < 0) return;
      auto e = cross_ghost(gh);
      if (e.first < 0) return;
      c = e.first, jin = e.second;
      face_in = m.cell_face[c][jin];
      const auto fv = m.face_vertices(face_in);
      t_in = param(vfix(m, fv[0]), vfix(m, fv[1]), vfix(m, fv[2]), t_in);
    }
    // The segment cannot end in a cell whose entry lies farther from its end than the cell's
    // diameter (at most the level-0 red edge length): the end test is skipped there.
    const double seg = ab.norm(), reach_end = 2 * red_edge_length(m.lat, 0);
    while (t_in <= t_stop) {
      const Tet& t = m.cell_v[c];
      const I3 V[4] = {vfix(m, t[0]), vfix(m, t[1]), vfix(m, t[2]), vfix(m, t[3])};
      const int j = exit_face(c, jin, V);
      const I3& x = V[kFace[j][0]];
      const I3& y = V[kFace[j][1]];
      const I3& z = V[kFace[j][2]];
      const std::int32_t f = m.cell_face[c][j];
      const bool may_end = (t_end - t_in) * seg <= reach_end;
      if (may_end && orient_sos(x, y, z, L.Q, kSoS2) < 0) {
        out.push_back({c, face_in, -1, t_in, std::max(t_in, t_end)});
        return;
      }
      const double t_out = param(x, y, z, t_in);
      out.push_back({c, face_in, f, t_in, t_out});
      t_in = t_out;
      const std::int32_t h = c * 4 + j;
      const std::int32_t o = m.face_half[f][0] == h ? m.face_half[f][1] : m.face_half[f][0];
      if (o >= 0) {
        c = o >> 2, jin = o & 3, face_in = f;
        continue;
      }
      auto e = cross_ghost(ghost_of_boundary(c, j));
      if (e.first < 0) return;
      c = e.first, jin = e.second;
      face_in = m.cell_face[c][jin];
      const auto fv = m.face_vertices(face_in);
      t_in = param(vfix(m, fv[0]), vfix(m, fv[1]), vfix(m, fv[2]), t_in);
    }
  }
};

}  // namespace

namespace {
void walk_segment_until(const TetMesh& m, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t_stop,
                        std::vector<WalkHit>& out, std::int32_t* start = nullptr) {
  out.clear();
  const Eigen::AlignedBox3d box = m.lat.grid_box();
  const Eigen::Vector3d d = b - a;
  double t0 = 0.0, t1 = 1.0;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0) {
      if (a[k] < box.min()[k] || a[k] > box.max()[k]) return;
      continue;
    }
    double u = (box.min()[k] - a[k]) / d[k], w = (box.max()[k] - a[k]) / d[k];
    if (u > w) std::swap(u, w);
    t0 = std::max(t0, u);
    t1 = std::min(t1, w);
  }
  if (!(t0 < t1)) return;
  const std::int64_t CS = m.lat.cube_fixed();
  auto fixed = [&](double t) {
    I3 p = m.lat.to_fixed(a + t * d);
    p.x = std::clamp<std::int64_t>(p.x, 1, m.lat.dims[0] * CS - 1);
    p.y = std::clamp<std::int64_t>(p.y, 1, m.lat.dims[1] * CS - 1);
    p.z = std::clamp<std::int64_t>(p.z, 1, m.lat.dims[2] * CS - 1);
    return p;
  };
  Walker w{m, Grid(m.lat), Line(fixed(t0), fixed(t1)), a, d, t1, out};
  w.t_stop = t_stop;
  w.run(t0, start);
}
}  // namespace

void walk_segment(const TetMesh& m, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                  std::vector<WalkHit>& out) {
  walk_segment_until(m, a, b, std::numeric_limits<double>::infinity(), out);
}

void walk_ray(const TetMesh& m, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
              std::vector<WalkHit>& out, double t_stop, std::int32_t* start) {
  out.clear();
  const Eigen::AlignedBox3d box = m.lat.grid_box();
  double tmax = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (dir[k] == 0.0) continue;
    const double u = (box.min()[k] - origin[k]) / dir[k], w = (box.max()[k] - origin[k]) / dir[k];
    tmax = std::min(tmax, std::max(u, w));
  }
  if (!(tmax > 0) || !std::isfinite(tmax)) return;
  walk_segment_until(m, origin, origin + tmax * dir, t_stop / tmax, out, start);
  for (auto& h : out) h.t_in *= tmax, h.t_out *= tmax;
}

}  // namespace tetmvs::tet
