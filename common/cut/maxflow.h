// Maximum flow / minimum s-t cut by the Boykov-Kolmogorov augmenting-path algorithm
// ("An experimental comparison of min-cut/max-flow algorithms for energy minimization in
// vision", PAMI 2004) on compact arrays: the graph's arcs in compressed sparse rows, each
// arc with its reverse (sister) arc, and the source and sink joined to the nodes by one
// net terminal capacity per node instead of arcs.
//
// Two search trees grow from the source and the sink over arcs with residual capacity;
// where they meet, the path is augmented, and the nodes cut off by saturated arcs
// (orphans) look for a new parent in their tree or become free. The trees carry depth
// labels, as in Goldberg et al.'s incremental breadth-first search (ESA 2011): an orphan
// takes a neighbour of smaller label as its parent without walking its path to the
// terminal, which BK's adoption does and which cost most of the time on the cut's graphs
// (tetrahedral meshes whose deep interior has no terminal capacity: paths of hundreds of
// arcs). Sequential and deterministic.
//
// The source side is the set of nodes reachable from the source in the final residual
// graph: the source side of the minimum cut whose source side is smallest, which every
// maximum flow gives. Residuals below a billionth of a typical capacity count as
// saturated: they are rounding, and whether one is exactly 0 depends on the order of the
// augmentations.
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
// per node: 1 when the node is reachable from the source in the residual graph (over
// residuals above the rounding). Returns
// the flow through the arcs and terminal capacities (not counting any flow the caller
// already cancelled between a node's two terminal capacities).
double max_flow(FlowGraph& g, std::vector<std::uint8_t>& source_side);

}  // namespace tetmvs::cut
