// Tests of the max-flow on compact arrays (common/cut/maxflow.h) against Boost.Graph's
// Boykov-Kolmogorov on random graphs: the same flow value, a cut whose capacity equals the
// flow, and a source side equal to the set reachable from the source in Boost's residual
// graph (the smallest minimum cut's source side, unique even when several cuts tie).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/property_map/property_map.hpp>
#include <random>
#include <vector>

#include "common/cut/maxflow.h"

using namespace tetmvs::cut;

namespace {

struct Problem {
  std::uint32_t n = 0;
  struct Edge {
    std::uint32_t u, v;
    double uv, vu;  // capacities of u->v and v->u
  };
  std::vector<Edge> edges;
  std::vector<double> source, sink;  // terminal capacities per node
};

// A random graph of n nodes with about `degree` neighbours each; integer capacities when
// `integer` (so that many cuts tie).
Problem random_problem(std::uint32_t n, int degree, bool integer, std::mt19937& rng) {
  Problem p;
  p.n = n;
  std::uniform_real_distribution<double> cap(0.0, 1.0);
  std::uniform_int_distribution<int> icap(0, 4);
  std::uniform_int_distribution<std::uint32_t> node(0, n - 1);
  const auto draw = [&] { return integer ? static_cast<double>(icap(rng)) : cap(rng); };
  for (std::uint32_t k = 0; k < n * degree / 2; ++k) {
    const std::uint32_t u = node(rng), v = node(rng);
    if (u != v) p.edges.push_back({u, v, draw(), draw()});
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    // most nodes tied to one terminal, some to both, some to none
    const int kind = static_cast<int>(rng() % 4);
    p.source.push_back(kind == 0 || kind == 2 ? 2 * draw() : 0.0);
    p.sink.push_back(kind == 1 || kind == 2 ? 2 * draw() : 0.0);
  }
  return p;
}

FlowGraph make_graph(const Problem& p, double& cancelled) {
  FlowGraph g;
  g.first.assign(p.n + 1, 0);
  for (const auto& e : p.edges) ++g.first[e.u + 1], ++g.first[e.v + 1];
  for (std::uint32_t i = 0; i < p.n; ++i) g.first[i + 1] += g.first[i];
  const std::size_t E = g.first[p.n];
  g.head.resize(E);
  g.sister.resize(E);
  g.cap.resize(E);
  std::vector<std::uint32_t> fill(g.first.begin(), g.first.end() - 1);
  for (const auto& e : p.edges) {
    const std::uint32_t a = fill[e.u]++, b = fill[e.v]++;
    g.head[a] = e.v, g.sister[a] = b, g.cap[a] = e.uv;
    g.head[b] = e.u, g.sister[b] = a, g.cap[b] = e.vu;
  }
  cancelled = 0;
  for (std::uint32_t i = 0; i < p.n; ++i) {
    g.terminal.push_back(p.source[i] - p.sink[i]);
    cancelled += std::min(p.source[i], p.sink[i]);
  }
  return g;
}

// Boost's flow (on a compressed sparse row graph with explicit source and sink nodes) and
// the nodes reachable from the source in its residual graph.
double boost_flow(const Problem& p, std::vector<std::uint8_t>& reachable) {
  using Graph = boost::compressed_sparse_row_graph<boost::directedS, boost::no_property, boost::no_property,
                                                   boost::no_property, std::uint32_t, std::uint32_t>;
  using Edge = boost::graph_traits<Graph>::edge_descriptor;
  const std::uint32_t s = p.n, t = p.n + 1, N = p.n + 2;
  struct Arc {
    std::uint32_t u, v;
    double cap;
    std::size_t rev;
  };
  std::vector<Arc> arcs;
  const auto add = [&](std::uint32_t u, std::uint32_t v, double uv, double vu) {
    arcs.push_back({u, v, uv, arcs.size() + 1});
    arcs.push_back({v, u, vu, arcs.size() - 1});
  };
  for (const auto& e : p.edges) add(e.u, e.v, e.uv, e.vu);
  for (std::uint32_t i = 0; i < p.n; ++i) {
    if (p.source[i] > 0) add(s, i, p.source[i], 0.0);
    if (p.sink[i] > 0) add(i, t, p.sink[i], 0.0);
  }
  // sorted by source node: CSR edge k is arcs[order[k]]
  std::vector<std::size_t> order(arcs.size()), where(arcs.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return arcs[a].u < arcs[b].u; });
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (std::size_t k = 0; k < order.size(); ++k) {
    pairs.emplace_back(arcs[order[k]].u, arcs[order[k]].v);
    where[order[k]] = k;
  }
  Graph g(boost::edges_are_sorted, pairs.begin(), pairs.end(), N);
  std::vector<Edge> desc(arcs.size());
  for (auto [it, end] = boost::edges(g); it != end; ++it) desc[boost::get(boost::edge_index, g, *it)] = *it;
  std::vector<double> cap(arcs.size()), res(arcs.size());
  std::vector<Edge> rev(arcs.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    cap[k] = arcs[order[k]].cap;
    rev[k] = desc[where[arcs[order[k]].rev]];
  }
  std::vector<Edge> pred(N);
  std::vector<boost::default_color_type> colour(N);
  std::vector<long> dist(N);
  const auto eidx = boost::get(boost::edge_index, g);
  const auto vidx = boost::get(boost::vertex_index, g);
  const double flow = boost::boykov_kolmogorov_max_flow(
      g, boost::make_iterator_property_map(cap.begin(), eidx), boost::make_iterator_property_map(res.begin(), eidx),
      boost::make_iterator_property_map(rev.begin(), eidx), boost::make_iterator_property_map(pred.begin(), vidx),
      boost::make_iterator_property_map(colour.begin(), vidx), boost::make_iterator_property_map(dist.begin(), vidx),
      vidx, s, t);
  std::vector<std::uint8_t> seen(N, 0);
  std::vector<std::uint32_t> stack{s};
  seen[s] = 1;
  while (!stack.empty()) {
    const std::uint32_t u = stack.back();
    stack.pop_back();
    for (auto [it, end] = boost::out_edges(u, g); it != end; ++it) {
      const auto v = static_cast<std::uint32_t>(boost::target(*it, g));
      if (res[boost::get(boost::edge_index, g, *it)] > 0 && !seen[v]) seen[v] = 1, stack.push_back(v);
    }
  }
  reachable.assign(seen.begin(), seen.begin() + p.n);
  return flow;
}

double cut_capacity(const Problem& p, const std::vector<std::uint8_t>& in) {
  double c = 0;
  for (const auto& e : p.edges) {
    if (in[e.u] && !in[e.v]) c += e.uv;
    if (!in[e.u] && in[e.v]) c += e.vu;
  }
  for (std::uint32_t i = 0; i < p.n; ++i) c += in[i] ? p.sink[i] : p.source[i];
  return c;
}

// max_flow and Boost on the same problem: the flows (max_flow's with the cancelled terminal
// flow added), max_flow's source side and the nodes Boost's residual graph reaches.
struct Solved {
  double flow = 0, expect = 0;
  std::vector<std::uint8_t> side, reachable;
};
Solved solve_both(const Problem& p) {
  Solved r;
  double cancelled = 0;
  FlowGraph g = make_graph(p, cancelled);
  r.flow = cancelled + max_flow(g, r.side);
  r.expect = boost_flow(p, r.reachable);
  return r;
}

}  // namespace

TEST(MaxFlow, MatchesBoostOnRandomGraphs) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    const bool integer = trial % 2 == 1;
    const Problem p = random_problem(50 + 37 * trial, 2 + trial % 6, integer, rng);
    const Solved r = solve_both(p);
    SCOPED_TRACE(trial);
    EXPECT_NEAR(r.flow, r.expect, 1e-9 * (1 + r.expect));
    EXPECT_NEAR(cut_capacity(p, r.side), r.flow, 1e-9 * (1 + r.flow));
    if (integer) {
      EXPECT_EQ(r.side, r.reachable);
    }  // exact arithmetic: the smallest cut, ties and all
  }
}

TEST(MaxFlow, EmptyAndTerminalOnlyGraphs) {
  FlowGraph g;
  std::vector<std::uint8_t> side;
  EXPECT_EQ(max_flow(g, side), 0.0);
  EXPECT_TRUE(side.empty());
  // three isolated nodes: source-tied, sink-tied, neither
  g.first = {0, 0, 0, 0};
  g.terminal = {1.5, -2.0, 0.0};
  EXPECT_EQ(max_flow(g, side), 0.0);
  EXPECT_EQ(side, (std::vector<std::uint8_t>{1, 0, 0}));
}

TEST(MaxFlow, ChainSaturatesItsWeakestArc) {
  // source -> 0 -> 1 -> 2 -> sink with arcs 3, 1, 2 and terminals 5 and 4: the flow is 1,
  // the cut between nodes 0 and 1
  FlowGraph g;
  g.first = {0, 1, 3, 4};
  g.head = {1, 0, 2, 1};
  g.sister = {1, 0, 3, 2};
  g.cap = {3, 0, 1, 0};
  g.terminal = {5, 0, -4};
  std::vector<std::uint8_t> side;
  EXPECT_DOUBLE_EQ(max_flow(g, side), 1.0);
  EXPECT_EQ(side, (std::vector<std::uint8_t>{1, 1, 0}));
}

TEST(MaxFlow, RoundingLeftInAnArcDoesNotDecideTheSide) {
  // source -> 0 -> 1 -> sink: the arc holds 0.1 + 0.2 (0.30000000000000004) and the sink
  // takes 0.3, so the arc keeps 5.6e-17 after the flow: rounding, not capacity. Node 1 is
  // on the sink side, as it would be with exact arithmetic (a tie, smallest source side).
  FlowGraph g;
  g.first = {0, 1, 2};
  g.head = {1, 0};
  g.sister = {1, 0};
  g.cap = {0.1 + 0.2, 0};
  g.terminal = {1.0, -0.3};
  std::vector<std::uint8_t> side;
  EXPECT_NEAR(max_flow(g, side), 0.3, 1e-15);
  ASSERT_GT(g.cap[0], 0.0);  // the rounding is there
  EXPECT_EQ(side, (std::vector<std::uint8_t>{1, 0}));
}

// The cut's graphs: a solid whose deep interior has no terminal capacity, a shell tied to the
// source and the air around it to the sink, so that augmenting paths run long and orphans are
// relabelled and freed often. A 3D grid, 6-neighbour, integer capacities (exact arithmetic:
// the source side must equal Boost's, ties and all).
TEST(MaxFlow, MatchesBoostOnAGridWithAnInteriorWithoutTerminals) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 4; ++trial) {
    const int n = 14 + 3 * trial;
    Problem p;
    p.n = static_cast<std::uint32_t>(n * n * n);
    const auto id = [n](int x, int y, int z) { return static_cast<std::uint32_t>((z * n + y) * n + x); };
    std::uniform_int_distribution<int> icap(1, 6), tcap(0, 3);
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          if (x + 1 < n) p.edges.push_back({id(x, y, z), id(x + 1, y, z), double(icap(rng)), double(icap(rng))});
          if (y + 1 < n) p.edges.push_back({id(x, y, z), id(x, y + 1, z), double(icap(rng)), double(icap(rng))});
          if (z + 1 < n) p.edges.push_back({id(x, y, z), id(x, y, z + 1), double(icap(rng)), double(icap(rng))});
          // distance from the grid's centre: interior (no terminal), shell (source), air (sink)
          const double c = (n - 1) / 2.0, r = std::sqrt((x - c) * (x - c) + (y - c) * (y - c) + (z - c) * (z - c));
          const double shell = 0.3 * n, air = 0.42 * n;
          p.source.push_back(r >= shell && r < air ? double(tcap(rng)) : 0.0);
          p.sink.push_back(r >= air ? double(tcap(rng)) : 0.0);
        }
    const Solved r = solve_both(p);
    SCOPED_TRACE(trial);
    EXPECT_GT(r.expect, 0.0);
    EXPECT_DOUBLE_EQ(r.flow, r.expect);
    EXPECT_EQ(r.side, r.reachable);
  }
}
