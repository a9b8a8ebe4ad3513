#include "common/cut/graph_cut.h"

#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/property_map/property_map.hpp>

#include "common/cut/face_cost.h"
#include "common/error.h"
#include "common/log.h"

namespace tetmvs::cut {

namespace {
using Graph = boost::compressed_sparse_row_graph<boost::directedS, boost::no_property,
                                                 boost::no_property, boost::no_property,
                                                 std::uint32_t, std::uint32_t>;
using Edge = boost::graph_traits<Graph>::edge_descriptor;
using Vertex = boost::graph_traits<Graph>::vertex_descriptor;
}  // namespace

CutResult min_cut(const tet::TetMesh& m, const std::vector<float>& omega,
                  const std::vector<std::int8_t>& labels, const CutOptions& opt) {
  const std::int32_t C = m.num_cells(), F = m.num_faces();
  require(static_cast<std::int64_t>(omega.size()) == 2LL * F, "min_cut: ", omega.size(),
          " face scores for ", F, " faces (need 2 per face)");
  require(static_cast<std::int32_t>(labels.size()) == C, "min_cut: ", labels.size(), " labels for ", C, " cells");
  require(opt.sigma > 0 && opt.lambda >= 0, "min_cut: sigma must be > 0 and lambda >= 0");

  // node of every cell: 0 = source (interior), 1 = sink (exterior), 2.. free cells
  std::vector<std::uint32_t> node(C);
  std::uint32_t n = 2;
  for (std::int32_t c = 0; c < C; ++c)
    node[c] = labels[c] == kInterior ? 0u : labels[c] == kExterior ? 1u : n++;

  // per face: the cost of each orientation; fixed costs of faces between two fixed sides
  const auto cost = [&](std::int32_t f, int o) {
    return face_cost(std::clamp<double>(omega[2 * f + o], 0.0, 1.0), m.face_area(f), opt.lambda, opt.sigma);
  };
  // directed edges sorted by source: count, then fill
  std::vector<std::uint64_t> start(n + 1, 0);
  const auto each_edge = [&](auto&& visit) {
    for (std::int32_t f = 0; f < F; ++f) {
      const std::int32_t a = m.face_cell(f, 0), b = m.face_cell(f, 1);
      const std::uint32_t na = node[a];
      const std::uint32_t nb = b < 0 ? 1u : node[b];  // outside the mesh = exterior
      if (na == nb) continue;
      visit(f, na, nb);
    }
  };
  each_edge([&](std::int32_t, std::uint32_t na, std::uint32_t nb) {
    ++start[na + 1];
    ++start[nb + 1];
  });
  // visibility term: terminal edges source->c (inside evidence) and c->sink (outside)
  const bool vis = opt.beta > 0 && opt.inside_evidence && opt.outside_evidence;
  if (vis) {
    require(static_cast<std::int32_t>(opt.inside_evidence->size()) == C &&
                static_cast<std::int32_t>(opt.outside_evidence->size()) == C,
            "min_cut: one evidence value per cell expected");
    for (std::int32_t c = 0; c < C; ++c) {
      if (node[c] < 2) continue;
      if ((*opt.inside_evidence)[c] > 0) ++start[0 + 1], ++start[node[c] + 1];
      if ((*opt.outside_evidence)[c] > 0) ++start[node[c] + 1], ++start[1 + 1];
    }
  }
  for (std::uint32_t v = 0; v < n; ++v) start[v + 1] += start[v];
  const std::uint64_t E = start[n];
  require(E < (1ULL << 32), "min_cut: graph too large (", E, " edges)");
  std::vector<std::uint32_t> target(E), rev(E);
  std::vector<double> cap(E);
  std::vector<std::uint64_t> fill(start.begin(), start.end() - 1);
  each_edge([&](std::int32_t f, std::uint32_t na, std::uint32_t nb) {
    const std::uint64_t e1 = fill[na]++, e2 = fill[nb]++;
    target[e1] = nb;
    target[e2] = na;
    rev[e1] = static_cast<std::uint32_t>(e2);
    rev[e2] = static_cast<std::uint32_t>(e1);
    // face normal points from cell 0 to cell 1; when the face is on the mesh boundary,
    // cell 0 is the only cell and "b" is the outside world.
    cap[e1] = cost(f, 0);  // na -> nb: na inside, nb outside
    cap[e2] = cost(f, 1);
  });
  std::vector<double> unary_in(vis ? C : 0, 0.0), unary_out(vis ? C : 0, 0.0);
  if (vis) {
    const auto add = [&](std::uint32_t a, std::uint32_t b, double capacity) {
      const std::uint64_t e1 = fill[a]++, e2 = fill[b]++;
      target[e1] = b;
      target[e2] = a;
      rev[e1] = static_cast<std::uint32_t>(e2);
      rev[e2] = static_cast<std::uint32_t>(e1);
      cap[e1] = capacity;
      cap[e2] = 0.0;
    };
    for (std::int32_t c = 0; c < C; ++c) {
      if (node[c] < 2) continue;
      const double s = opt.beta * std::cbrt(m.cell_volume(c) * m.cell_volume(c));
      unary_in[c] = s * (*opt.inside_evidence)[c];
      unary_out[c] = s * (*opt.outside_evidence)[c];
      if ((*opt.inside_evidence)[c] > 0) add(0u, node[c], unary_in[c]);     // cut when c ends outside
      if ((*opt.outside_evidence)[c] > 0) add(node[c], 1u, unary_out[c]);   // cut when c ends inside
    }
  }
  // CSR graph from the sorted edge list
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  pairs.reserve(E);
  for (std::uint32_t v = 0; v < n; ++v)
    for (std::uint64_t e = start[v]; e < start[v + 1]; ++e) pairs.emplace_back(v, target[e]);
  Graph g(boost::edges_are_sorted, pairs.begin(), pairs.end(), n);
  std::vector<std::pair<std::uint32_t, std::uint32_t>>().swap(pairs);
  std::vector<Edge> desc(E);
  for (auto [it, end] = boost::edges(g); it != end; ++it) desc[boost::get(boost::edge_index, g, *it)] = *it;
  // sanity: the CSR kept our order
  for (std::uint64_t e = 0; e < std::min<std::uint64_t>(E, 16); ++e)
    require(boost::target(desc[e], g) == target[e], "min_cut: internal CSR order mismatch");
  std::vector<Edge> rev_desc(E);
  for (std::uint64_t e = 0; e < E; ++e) rev_desc[e] = desc[rev[e]];
  std::vector<std::uint32_t>().swap(rev);
  std::vector<double> residual(E, 0.0);
  std::vector<Edge> pred(n);
  std::vector<boost::default_color_type> colour(n);
  std::vector<std::int64_t> dist(n, 0);
  const auto eidx = boost::get(boost::edge_index, g);
  const auto vidx = boost::get(boost::vertex_index, g);

  CutResult r;
  r.graph_nodes = n;
  r.graph_edges = static_cast<std::int64_t>(E);
  r.graph_bytes = static_cast<std::int64_t>(E * (sizeof(std::uint32_t) + 2 * sizeof(double) + sizeof(Edge) + sizeof(std::uint32_t)) +
                                            n * (sizeof(std::uint64_t) + sizeof(Edge) + 1 + sizeof(std::int64_t)));
  double flow = 0;
  if (E > 0) {
    flow = boost::boykov_kolmogorov_max_flow(
        g, boost::make_iterator_property_map(cap.begin(), eidx),
        boost::make_iterator_property_map(residual.begin(), eidx),
        boost::make_iterator_property_map(rev_desc.begin(), eidx),
        boost::make_iterator_property_map(pred.begin(), vidx),
        boost::make_iterator_property_map(colour.begin(), vidx),
        boost::make_iterator_property_map(dist.begin(), vidx), vidx, Vertex(0), Vertex(1));
  }
  r.max_flow = flow;
  // Source side = the source search tree (black) at termination.
  const auto black = boost::color_traits<boost::default_color_type>::black();
  r.inside.assign(C, 0);
  for (std::int32_t c = 0; c < C; ++c) {
    const std::uint32_t v = node[c];
    r.inside[c] = v == 0 ? 1 : v == 1 ? 0 : (colour[v] == black ? 1 : 0);
  }
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
  return r;
}

}  // namespace tetmvs::cut
