#include "common/cut/surface.h"

#include <algorithm>
#include <array>
#include <set>
#include <unordered_map>

#include "common/error.h"

namespace tetmvs::cut {

namespace {

// Local index (0..3) of vertex v in cell c, or -1.
int local_index(const tet::Tet& t, std::int32_t v) {
  for (int k = 0; k < 4; ++k)
    if (t[k] == v) return k;
  return -1;
}

enum class Pairing { kInside, kOutside };

// The extraction state: cut triangles, the pairing of triangles across each mesh edge,
// and the vertex copy (fan) of every corner.
class Extractor {
 public:
  Extractor(const tet::TetMesh& m, const std::vector<std::uint8_t>& inside) : m_(m), inside_(inside) {
    const std::int32_t F = m.num_faces();
    for (std::int32_t f = 0; f < F; ++f) {
      const std::int32_t a = m.face_cell(f, 0), b = m.face_cell(f, 1);
      if (is_in(a) == is_in(b)) continue;
      const std::int32_t h = is_in(a) ? m.face_half[f][0] : m.face_half[f][1];
      tri_of_half_.emplace(h, static_cast<std::int32_t>(half_.size()));
      half_.push_back(h);
    }
    T_ = static_cast<std::int64_t>(half_.size());
    partner_.assign(3 * T_, -1);
    label_.assign(3 * T_, -1);
    // corners of every mesh vertex (CSR), in corner order
    first_.assign(m.num_vertices() + 1, 0);
    for (std::int64_t c = 0; c < 3 * T_; ++c) ++first_[corner_vertex(c) + 1];
    for (std::size_t v = 1; v < first_.size(); ++v) first_[v] += first_[v - 1];
    corners_.resize(3 * T_);
    std::vector<std::int64_t> fill(first_.begin(), first_.end() - 1);
    for (std::int64_t c = 0; c < 3 * T_; ++c) corners_[fill[corner_vertex(c)]++] = c;
  }

  std::int64_t triangles() const { return T_; }
  std::int32_t half(std::int64_t t) const { return half_[t]; }
  // Vertex k of triangle t: the outward vertex order of its inside cell's face.
  std::int32_t tri_vertex(std::int64_t t, int k) const {
    const std::int32_t h = half_[t];
    return m_.cell_v[h >> 2][tet::kFace[h & 3][k]];
  }
  std::int32_t corner_vertex(std::int64_t c) const { return tri_vertex(c / 3, static_cast<int>(c % 3)); }
  std::int64_t label(std::int64_t c) const { return label_[c]; }
  // Edge e = corner e -> corner e+1 of triangle t is glued to edge partner(t*3+e).
  std::int64_t partner(std::int64_t te) const { return partner_[te]; }

  // Pairs the cut triangles around every mesh edge through the inside sectors.
  void pair_all() {
    for (std::int64_t te = 0; te < 3 * T_; ++te)
      if (partner_[te] < 0) pair_edge(te, Pairing::kInside);
  }

  // Labels every corner with its fan: the cycle of corners of one mesh vertex linked by
  // the pairing across the triangles' edges at that vertex.
  void label_all() {
    for (std::int64_t c = 0; c < 3 * T_; ++c)
      if (label_[c] < 0) walk_fan(c);
  }

  // Triangle edges (t*3+e, one per glued pair) whose two vertex copies are shared by
  // another pair: the non-manifold spots, sorted by their copies then by triangle.
  std::vector<std::int64_t> bad_pairs() const {
    std::vector<std::pair<std::array<std::int64_t, 2>, std::int64_t>> keys;
    keys.reserve(3 * T_ / 2);
    for (std::int64_t te = 0; te < 3 * T_; ++te)
      if (te < partner_[te]) keys.push_back({edge_key(te), te});
    return duplicated(keys);
  }

  // Bad pairs among the edges at mesh vertices a and b.
  std::int64_t bad_count_at(std::int32_t a, std::int32_t b) const {
    auto keys = pair_keys_at(a, b);
    return static_cast<std::int64_t>(duplicated(keys).size());
  }

  // Whether pair te shares both vertex copies with another pair.
  bool is_bad(std::int64_t te) const {
    const std::int64_t lo = std::min(te, partner_[te]);
    const auto key = edge_key(lo);
    for (const auto& [k, p] : pair_keys_at(corner_vertex(te), -1))
      if (k == key && p != lo) return true;
    return false;
  }

  // Re-pairs the triangles around the mesh edge of triangle edge te and relabels the fans
  // of its two end vertices.
  void repair(std::int64_t te, Pairing p) {
    const std::int32_t a = corner_vertex(te), b = corner_vertex(te / 3 * 3 + (te % 3 + 1) % 3);
    pair_edge(te, p);
    for (const std::int32_t v : {a, b}) {
      for (std::int64_t i = first_[v]; i < first_[v + 1]; ++i) label_[corners_[i]] = -1;
      for (std::int64_t i = first_[v]; i < first_[v + 1]; ++i)
        if (label_[corners_[i]] < 0) walk_fan(corners_[i]);
    }
  }

 private:
  bool is_in(std::int32_t c) const { return c >= 0 && inside_[c] != 0; }

  // (copies, lowest triangle edge) of every glued pair at mesh vertices a and b (b may be -1).
  std::vector<std::pair<std::array<std::int64_t, 2>, std::int64_t>> pair_keys_at(std::int32_t a, std::int32_t b) const {
    std::vector<std::pair<std::array<std::int64_t, 2>, std::int64_t>> keys;
    for (const std::int32_t v : {a, b}) {
      if (v < 0) continue;
      for (std::int64_t i = first_[v]; i < first_[v + 1]; ++i) {
        const std::int64_t c = corners_[i], t = c / 3, k = c % 3;
        for (const std::int64_t te : {t * 3 + k, t * 3 + (k + 2) % 3}) {
          const std::int64_t lo = std::min(te, partner_[te]);
          keys.push_back({edge_key(lo), lo});
        }
      }
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    return keys;
  }

  std::array<std::int64_t, 2> edge_key(std::int64_t te) const {
    const std::int64_t t = te / 3, k = te % 3;
    const std::int64_t x = label_[te], y = label_[t * 3 + (k + 1) % 3];
    return {std::min(x, y), std::max(x, y)};
  }

  // From keys sorted or not: the representative (smallest) pair of every key beyond the
  // first, i.e. the pairs that share their copies with an earlier pair.
  static std::vector<std::int64_t> duplicated(std::vector<std::pair<std::array<std::int64_t, 2>, std::int64_t>>& keys) {
    std::sort(keys.begin(), keys.end());
    std::vector<std::int64_t> out;
    for (std::size_t i = 1; i < keys.size(); ++i)
      if (keys[i].first == keys[i - 1].first) out.push_back(keys[i].second);
    return out;
  }

  // Walks the fan of corner c0 and gives all its corners a new label.
  void walk_fan(std::int64_t c0) {
    const std::int64_t id = next_label_++;
    const std::int32_t v = corner_vertex(c0);
    std::int64_t c = c0;
    int leave = static_cast<int>(c0 % 3);  // leave through the edge starting at the corner
    for (std::int64_t guard = 0;; ++guard) {
      require(guard <= 3 * T_, "cut_surface: a vertex fan does not close");
      label_[c] = id;
      const std::int64_t t = c / 3;
      const std::int64_t pe = partner_[t * 3 + leave];
      require(pe >= 0, "cut_surface: an unpaired triangle edge");
      const std::int64_t p = pe / 3, e = pe % 3;
      // the corner of v in p is one end of its edge e; leave p through its other edge at v
      int q, next;
      if (tri_vertex(p, static_cast<int>(e)) == v) {
        q = static_cast<int>(e);
        next = (q + 2) % 3;
      } else {
        q = static_cast<int>((e + 1) % 3);
        next = q;
      }
      require(tri_vertex(p, q) == v, "cut_surface: a glued edge with different vertices");
      c = p * 3 + q;
      leave = next;
      if (c == c0) return;
      require(label_[c] < 0, "cut_surface: a vertex fan is not a cycle");
    }
  }

  // The edge index (0..2) of triangle t joining mesh vertices a and b.
  int edge_of(std::int64_t t, std::int32_t a, std::int32_t b) const {
    for (int k = 0; k < 3; ++k) {
      const std::int32_t x = tri_vertex(t, k), y = tri_vertex(t, (k + 1) % 3);
      if ((x == a && y == b) || (x == b && y == a)) return k;
    }
    fail("cut_surface: a triangle around an edge does not hold the edge");
  }

  // The cells around the mesh edge of triangle edge te in rotation order, and pairs its cut
  // triangles: each with the next cut triangle across an inside run of cells (kInside) or
  // across an outside run (kOutside; the space beyond the domain is one outside cell).
  void pair_edge(std::int64_t te, Pairing mode) {
    const std::int64_t t0 = te / 3;
    const std::int32_t u = corner_vertex(te), v = corner_vertex(t0 * 3 + (te % 3 + 1) % 3);
    // ring[i]: a cell; gap i lies between ring[i] and ring[i+1] (cyclic) and is given by
    // the half-faces of its two sides (-1 beyond the domain).
    struct Gap {
      std::int32_t h_prev, h_next;
    };
    std::vector<std::int32_t> ring;
    std::vector<Gap> gaps;
    // walk from cell c0 leaving through local face j, until back at c0 or out of the domain
    const auto walk = [&](std::int32_t c0, int j0, std::vector<std::int32_t>& cells, std::vector<Gap>& gs) {
      std::int32_t c = c0;
      int j = j0;
      cells.push_back(c);
      for (int guard = 0;; ++guard) {
        require(guard < 100000, "cut_surface: the cells around an edge do not close");
        const std::int32_t nb = m_.neighbour(c, j);
        if (nb < 0) {
          gs.push_back({c * 4 + j, -1});
          return false;
        }
        const tet::Tet& tc = m_.cell_v[c];
        const tet::Tet& tn = m_.cell_v[nb];
        int jb = -1;
        for (int q = 0; q < 4; ++q)
          if (m_.neighbour(nb, q) == c && local_index(tc, tn[q]) < 0) jb = q;
        require(jb >= 0, "cut_surface: inconsistent cell adjacency");
        gs.push_back({c * 4 + j, nb * 4 + jb});
        if (nb == c0) return true;
        // leave nb through its other face holding u and v
        const int lu = local_index(tn, u), lv = local_index(tn, v);
        int jn = -1;
        for (int q = 0; q < 4; ++q)
          if (q != lu && q != lv && q != jb) jn = q;
        c = nb;
        j = jn;
        cells.push_back(c);
      }
    };
    const std::int32_t c0 = half_[t0] >> 2, j0 = half_[t0] & 3;
    if (!walk(c0, j0, ring, gaps)) {
      // open fan at the domain boundary: walk the other way from c0 and prepend, then
      // close the ring with the space beyond the domain
      const tet::Tet& tc = m_.cell_v[c0];
      const int lu = local_index(tc, u), lv = local_index(tc, v);
      int j1 = -1;
      for (int q = 0; q < 4; ++q)
        if (q != lu && q != lv && q != j0) j1 = q;
      std::vector<std::int32_t> back_cells;
      std::vector<Gap> back_gaps;
      require(!walk(c0, j1, back_cells, back_gaps), "cut_surface: a fan closes one way but not the other");
      // back_cells = c0, d1, d2, ... dk; back_gaps[i] between back_cells[i] and [i+1],
      // the last one leads out of the domain. Ring: dk ... d1, c0, (forward cells), out.
      std::vector<std::int32_t> r2;
      std::vector<Gap> g2;
      for (std::size_t i = back_cells.size(); i-- > 1;) {
        r2.push_back(back_cells[i]);
        g2.push_back({back_gaps[i - 1].h_next, back_gaps[i - 1].h_prev});
      }
      r2.insert(r2.end(), ring.begin(), ring.end());
      g2.insert(g2.end(), gaps.begin(), gaps.end());  // ends with the gap out of the domain
      r2.push_back(-1);                                // the outside beyond the domain
      g2.push_back({-1, back_gaps.back().h_prev});     // from beyond into dk
      ring.swap(r2);
      gaps.swap(g2);
    }
    const std::size_t n = ring.size();
    require(gaps.size() == n, "cut_surface: ring bookkeeping");
    // cut gaps in ring order; the triangle of each and whether an inside run follows it
    std::vector<std::int64_t> cut_tri;
    std::vector<std::uint8_t> starts_inside;
    for (std::size_t i = 0; i < n; ++i) {
      const std::int32_t a = ring[i], b = ring[(i + 1) % n];
      if (is_in(a) == is_in(b)) continue;
      const std::int32_t h = is_in(a) ? gaps[i].h_prev : gaps[i].h_next;
      cut_tri.push_back(tri_of_half_.at(h));
      starts_inside.push_back(is_in(b));
    }
    const std::size_t k = cut_tri.size();
    require(k >= 2 && k % 2 == 0, "cut_surface: an odd number of cut faces around an edge");
    const bool want = mode == Pairing::kInside;
    for (std::size_t i = 0; i < k; ++i) {
      if ((starts_inside[i] != 0) != want) continue;
      const std::int64_t a = cut_tri[i], b = cut_tri[(i + 1) % k];
      const std::int64_t ea = a * 3 + edge_of(a, u, v), eb = b * 3 + edge_of(b, u, v);
      partner_[ea] = eb;
      partner_[eb] = ea;
    }
  }

  const tet::TetMesh& m_;
  const std::vector<std::uint8_t>& inside_;
  std::vector<std::int32_t> half_;  // per triangle: the half-face of its inside cell
  std::unordered_map<std::int32_t, std::int32_t> tri_of_half_;
  std::int64_t T_ = 0;
  std::vector<std::int64_t> partner_;  // per triangle edge
  std::vector<std::int64_t> label_;    // per corner: its fan
  std::int64_t next_label_ = 0;
  std::vector<std::int64_t> first_, corners_;  // corners of each mesh vertex
};

}  // namespace

TriMesh cut_surface(const tet::TetMesh& m, const std::vector<std::uint8_t>& inside, SurfaceStats* stats,
                    std::vector<std::int32_t>* face_ids, const SurfaceOptions& opt) {
  require(static_cast<std::int32_t>(inside.size()) == m.num_cells(), "cut_surface: one flag per cell expected");
  Extractor x(m, inside);
  const std::int64_t T = x.triangles();
  x.pair_all();
  x.label_all();
  SurfaceStats st;
  st.faces = T;
  // 1. Re-pair around the edges where two sheets share both vertex copies: through the
  //    outside sectors instead of the inside ones, kept when it lowers the count of bad
  //    pairs at the edge's two vertices. Sequential, in a fixed order.
  std::vector<std::int64_t> bad = x.bad_pairs();
  st.nonmanifold_edges = static_cast<std::int64_t>(bad.size());
  if (opt.repair) {
    std::set<std::pair<std::int32_t, std::int32_t>> outside_paired;  // mesh edges re-paired
    for (int pass = 0; pass < 4 && !bad.empty(); ++pass) {
      for (const std::int64_t te : bad) {
        if (!x.is_bad(te)) continue;  // resolved by an earlier re-pairing
        const std::int32_t a = x.corner_vertex(te), b = x.corner_vertex(te / 3 * 3 + (te % 3 + 1) % 3);
        const std::pair<std::int32_t, std::int32_t> edge{std::min(a, b), std::max(a, b)};
        const bool was_outside = outside_paired.count(edge) != 0;
        const std::int64_t before = x.bad_count_at(a, b);
        x.repair(te, was_outside ? Pairing::kInside : Pairing::kOutside);
        if (x.bad_count_at(a, b) >= before) {
          x.repair(te, was_outside ? Pairing::kOutside : Pairing::kInside);
          continue;
        }
        if (was_outside)
          outside_paired.erase(edge);
        else
          outside_paired.insert(edge);
      }
      std::vector<std::int64_t> left = x.bad_pairs();
      const bool progress = left.size() < bad.size();
      bad.swap(left);
      if (!progress) break;
    }
    st.repaired_edges = static_cast<std::int64_t>(outside_paired.size());
  }
  // 2. Output vertices: one per fan, numbered in order of first corner.
  TriMesh out;
  std::unordered_map<std::int64_t, std::int32_t> vid;
  std::vector<std::int32_t> corner_out(3 * T);
  std::vector<std::uint8_t> used(m.num_vertices(), 0);
  std::int64_t distinct = 0;
  for (std::int64_t c = 0; c < 3 * T; ++c) {
    const auto [it, fresh] = vid.emplace(x.label(c), static_cast<std::int32_t>(out.V.size()));
    if (fresh) {
      const std::int32_t mv = x.corner_vertex(c);
      out.V.push_back(m.vertex(mv));
      if (!used[mv]) used[mv] = 1, ++distinct;
    }
    corner_out[c] = it->second;
  }
  st.split_vertices = static_cast<std::int64_t>(out.V.size()) - distinct;
  // 3. Pairs that still share both copies with another pair get their own midpoint vertex
  //    on the edge (both triangles of the pair are split there), so every output edge has
  //    two triangles.
  std::vector<std::int32_t> mid(3 * T, -1);
  for (const std::int64_t te : bad) {
    const std::int64_t pe = x.partner(te);
    const std::int32_t a = x.corner_vertex(te), b = x.corner_vertex(te / 3 * 3 + (te % 3 + 1) % 3);
    mid[te] = mid[pe] = static_cast<std::int32_t>(out.V.size());
    out.V.push_back(0.5 * (m.vertex(a) + m.vertex(b)));
    ++st.split_edges;
  }
  std::vector<std::int32_t> ids;
  out.F.reserve(T + 2 * st.split_edges);
  ids.reserve(T + 2 * st.split_edges);
  for (std::int64_t t = 0; t < T; ++t) {
    const std::int32_t face = m.cell_face[x.half(t) >> 2][x.half(t) & 3];
    const std::int32_t* c = &corner_out[3 * t];
    const std::int32_t* e = &mid[3 * t];
    const int s = (e[0] >= 0) + (e[1] >= 0) + (e[2] >= 0);
    const auto emit = [&](std::int32_t p, std::int32_t q, std::int32_t r) {
      out.F.push_back({p, q, r});
      ids.push_back(face);
    };
    if (s == 0) {
      emit(c[0], c[1], c[2]);
    } else if (s == 1) {
      const int k = e[0] >= 0 ? 0 : e[1] >= 0 ? 1 : 2;  // split edge: corner k -> k+1
      const std::int32_t a = c[k], b = c[(k + 1) % 3], d = c[(k + 2) % 3], mm = e[k];
      emit(a, mm, d);
      emit(mm, b, d);
    } else if (s == 2) {
      const int k = e[0] < 0 ? 0 : e[1] < 0 ? 1 : 2;  // the unsplit edge: corner k -> k+1
      const std::int32_t a = c[k], b = c[(k + 1) % 3], d = c[(k + 2) % 3];
      const std::int32_t m1 = e[(k + 1) % 3], m2 = e[(k + 2) % 3];  // on b-d and d-a
      emit(a, b, m1);
      emit(a, m1, m2);
      emit(m1, d, m2);
    } else {
      emit(c[0], e[0], e[2]);
      emit(e[0], c[1], e[1]);
      emit(e[2], e[1], c[2]);
      emit(e[0], e[1], e[2]);
    }
  }
  if (stats) *stats = st;
  if (face_ids) face_ids->swap(ids);
  return out;
}

}  // namespace tetmvs::cut
