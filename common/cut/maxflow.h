// Maximum flow / minimum s-t cut by the Boykov-Kolmogorov augmenting-path algorithm
// ("An experimental comparison of min-cut/max-flow algorithms for energy minimization in
// vision", PAMI 2004) on compact arrays: the graph's arcs in compressed sparse rows, each
// arc with its reverse (sister) arc, and the source and sink joined to the nodes by one
// net terminal capacity per node instead of arcs.
//
// Two search trees grow from the source and the sink over arcs with residual capacity;
// where they meet, the path is augmented, and the nodes cut off by saturated arcs
// (orphans) look for a new parent in their tree or become free. At the end the source
// tree holds exactly the nodes reachable from the source in the residual graph: the
// source side of the minimum cut whose source side is smallest (unique for a given
// graph, whatever the order of the search). Sequential and deterministic.
#pragma once
#include <cstdint>
#include <vector>

namespace tetmvs::cut {

struct FlowGraph {
  // Arcs of node i are first[i] .. first[i+1]-1 (first has n+1 entries).
  std::vector<std::uint32_t> first;
  std::vector<std::uint32_t> head;    // per arc: the node it leads to
  std::vector<std::uint32_t> sister;  // per arc: the reverse arc (head -> tail)
  std::vector<double> cap;            // per arc: capacity (>= 0); residual after max_flow
  // Per node: source capacity minus sink capacity (the part of a node's two terminal
  // capacities that their common flow leaves); residual after max_flow.
  std::vector<double> terminal;
  std::uint32_t nodes() const { return first.empty() ? 0u : static_cast<std::uint32_t>(first.size() - 1); }
  std::uint64_t arcs() const { return head.size(); }
  std::int64_t bytes() const;  // memory of the arrays above and of max_flow's work arrays
};

// Runs the algorithm on g (its capacities become residuals). source_side receives one flag
// per node: 1 when the node is reachable from the source in the residual graph. Returns
// the flow through the arcs and terminal capacities (not counting any flow the caller
// already cancelled between a node's two terminal capacities).
double max_flow(FlowGraph& g, std::vector<std::uint8_t>& source_side);

}  // namespace tetmvs::cut
