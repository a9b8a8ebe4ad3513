#include "common/cut/graph_cut.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "common/cut/face_cost.h"
#include "common/cut/maxflow.h"
#include "common/error.h"

namespace tetmvs::cut {

namespace {
constexpr std::uint32_t kFixed = 0xFFFFFFFFu;  // node of a labelled cell: none
}  // namespace

void CutOptions::check() const { check_param_ranges(*this); }

CutResult min_cut(const tet::TetMesh& m, const std::vector<float>& omega,
                  const std::vector<std::int8_t>& labels, const CutOptions& opt) {
  const std::int32_t C = m.num_cells(), F = m.num_faces();
  require(static_cast<std::int64_t>(omega.size()) == 2LL * F, "min_cut: ", omega.size(),
          " face scores for ", F, " faces (need 2 per face)");
  require(static_cast<std::int32_t>(labels.size()) == C, "min_cut: ", labels.size(), " labels for ", C, " cells");
  opt.check();
  const bool vis = opt.beta > 0 && opt.inside_evidence && opt.outside_evidence;
  if (vis)
    require(static_cast<std::int32_t>(opt.inside_evidence->size()) == C &&
                static_cast<std::int32_t>(opt.outside_evidence->size()) == C,
            "min_cut: one evidence value per cell expected");

  // Nodes: the free cells, in cell order. Interior cells are the source, exterior cells
  // and the world beyond the mesh boundary the sink; an arc joins two free cells only, a
  // face between a free cell and a labelled one adds to the free cell's terminal capacity.
  std::vector<std::uint32_t> node(C, kFixed);
  std::uint32_t n = 0;
  for (std::int32_t c = 0; c < C; ++c)
    if (labels[c] == kFree) node[c] = n++;
  // the cost of face f when the cell on its side k is inside and the other one outside
  const auto cost = [&](std::int32_t f, int k) {
    return face_cost(std::clamp<double>(omega[2 * f + k], 0.0, 1.0), m.face_area(f), opt.lambda, opt.sigma);
  };
  // the cell across local face j of cell c (-1 beyond the boundary) and c's side of that face
  const auto across = [&](std::int32_t c, int j, std::int32_t& f, int& side) {
    f = m.cell_face[c][j];
    side = m.face_half[f][0] == c * 4 + j ? 0 : 1;
    const std::int32_t h = m.face_half[f][1 - side];
    return h < 0 ? -1 : h >> 2;
  };
  // free neighbours of every free cell (bit j: across local face j), then the arc rows
  std::vector<std::uint8_t> free_nb(C, 0);
#pragma omp parallel for schedule(static)
  for (std::int32_t c = 0; c < C; ++c) {
    if (node[c] == kFixed) continue;
    std::uint8_t mask = 0;
    for (int j = 0; j < 4; ++j) {
      std::int32_t f;
      int side;
      const std::int32_t d = across(c, j, f, side);
      if (d >= 0 && node[d] != kFixed) mask |= static_cast<std::uint8_t>(1u << j);
    }
    free_nb[c] = mask;
  }
  FlowGraph g;
  g.first.assign(n + 1, 0);
  for (std::int32_t c = 0; c < C; ++c)
    if (node[c] != kFixed) g.first[node[c] + 1] = g.first[node[c]] + std::popcount(free_nb[c]);
  const std::uint64_t E = g.first[n];
  require(E < 0xFFFFFFF0ULL, "min_cut: graph too large (", E, " arcs)");
  g.head.resize(E);
  g.sister.resize(E);
  g.cap.resize(E);
  g.terminal.assign(n, 0.0);
  std::vector<double> cancelled(n, 0.0);  // flow common to a node's two terminal capacities
  std::vector<double> unary_in(vis ? C : 0, 0.0), unary_out(vis ? C : 0, 0.0);
#pragma omp parallel for schedule(static)
  for (std::int32_t c = 0; c < C; ++c) {
    const std::uint32_t i = node[c];
    if (i == kFixed) continue;
    double to_source = 0, to_sink = 0;  // c's capacities from the source and to the sink
    std::uint32_t a = g.first[i];
    for (int j = 0; j < 4; ++j) {
      std::int32_t f;
      int side;
      const std::int32_t d = across(c, j, f, side);
      if (d < 0 || labels[d] == kExterior) {
        to_sink += cost(f, side);  // cut when c ends inside
      } else if (labels[d] == kInterior) {
        to_source += cost(f, 1 - side);  // cut when c ends outside
      } else {
        const int jd = m.face_half[f][1 - side] & 3;  // d's local face
        g.head[a] = node[d];
        g.sister[a] = g.first[node[d]] + std::popcount(static_cast<unsigned>(free_nb[d] & ((1u << jd) - 1)));
        g.cap[a] = cost(f, side);
        ++a;
      }
    }
    if (vis) {
      const double s = opt.beta * std::cbrt(m.cell_volume(c) * m.cell_volume(c));
      unary_in[c] = s * (*opt.inside_evidence)[c];    // cut when c ends outside
      unary_out[c] = CutOptions::kOutsideShare * s * (*opt.outside_evidence)[c];  // cut when c ends inside
      to_source += unary_in[c];
      to_sink += unary_out[c];
    }
    g.terminal[i] = to_source - to_sink;
    cancelled[i] = std::min(to_source, to_sink);
  }
  // faces between an interior cell and the sink side: cut whatever the free cells do
  double fixed_flow = 0;
  for (std::int32_t f = 0; f < F; ++f) {
    const std::int32_t a = m.face_cell(f, 0), b = m.face_cell(f, 1);
    const std::int8_t la = labels[a], lb = b < 0 ? std::int8_t{kExterior} : labels[b];
    if (la == kInterior && lb == kExterior) fixed_flow += cost(f, 0);
    if (la == kExterior && lb == kInterior) fixed_flow += cost(f, 1);
  }
  for (std::uint32_t i = 0; i < n; ++i) fixed_flow += cancelled[i];
  std::vector<double>().swap(cancelled);

  CutResult r;
  r.graph_nodes = n + 2;  // with the source and the sink
  std::int64_t links = 0;
  for (std::uint32_t i = 0; i < n; ++i) links += g.terminal[i] != 0;
  r.graph_edges = static_cast<std::int64_t>(E) + links;
  r.graph_bytes = g.bytes() + static_cast<std::int64_t>(C * (sizeof(std::uint32_t) + 1));
  std::vector<std::uint8_t> source_side;
  r.max_flow = fixed_flow + max_flow(g, source_side);
  r.inside.assign(C, 0);
  for (std::int32_t c = 0; c < C; ++c)
    r.inside[c] = labels[c] == kInterior ? 1 : labels[c] == kExterior ? 0 : source_side[node[c]];
  for (std::int32_t f = 0; f < F; ++f) {
    const std::int32_t a = m.face_cell(f, 0), b = m.face_cell(f, 1);
    const int ia = r.inside[a], ib = b < 0 ? 0 : r.inside[b];
    if (ia == ib) continue;
    const int o = ia ? 0 : 1;  // orientation whose normal points outward
    const double area = m.face_area(f);
    const double d = data_term(std::clamp<double>(omega[2 * f + o], 0.0, 1.0), opt.sigma) * area;
    r.data_energy += d;
    r.area_energy += opt.lambda * area;
    r.cut_area += area;
    ++r.cut_faces;
  }
  if (vis)
    for (std::int32_t c = 0; c < C; ++c) r.visibility_energy += r.inside[c] ? unary_out[c] : unary_in[c];
  r.energy = r.data_energy + r.area_energy + r.visibility_energy;
  // a minimum cut's energy equals the maximum flow (up to rounding)
  require(std::abs(r.energy - r.max_flow) <= 1e-9 * std::max(1.0, std::abs(r.energy)), "min_cut: internal error: cut energy ",
          r.energy, " differs from the maximum flow ", r.max_flow);
  return r;
}

}  // namespace tetmvs::cut
