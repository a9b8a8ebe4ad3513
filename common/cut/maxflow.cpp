#include "common/cut/maxflow.h"

#include <algorithm>
#include <limits>

#include "common/error.h"

namespace tetmvs::cut {

namespace {

// parent of a node: an arc index (the arc from the node to its parent), or one of these
constexpr std::uint32_t kFreeNode = 0xFFFFFFFFu;  // in no tree
constexpr std::uint32_t kTerminal = 0xFFFFFFFEu;  // child of the source or the sink
constexpr std::uint32_t kOrphan = 0xFFFFFFFDu;    // lost its parent arc, being re-attached
constexpr std::uint32_t kNoDist = 0x7FFFFFFFu;

struct Node {
  std::uint32_t parent = kFreeNode;
  std::uint32_t next = kFreeNode;  // next in the active queue; itself when last; kFreeNode when not queued
  std::uint32_t stamp = 0;         // time at which dist was last known right
  std::uint32_t dist : 31 = 0;     // arcs to the terminal along the tree
  std::uint32_t sink : 1 = 0;      // 1: in the sink tree
};

class Solver {
 public:
  explicit Solver(FlowGraph& g) : g_(g), n_(g.nodes()), node_(n_) {}

  double run() {
    push_short_paths();
    for (std::uint32_t i = 0; i < n_; ++i) {
      const double t = g_.terminal[i];
      if (t == 0) continue;
      node_[i].parent = kTerminal;
      node_[i].sink = t < 0;
      node_[i].dist = 1;
      activate(i);
    }
    std::uint32_t current = kFreeNode;
    for (;;) {
      std::uint32_t i = current;
      if (i != kFreeNode) {
        node_[i].next = kFreeNode;
        if (node_[i].parent == kFreeNode) i = kFreeNode;
      }
      if (i == kFreeNode && (i = pop_active()) == kFreeNode) break;
      const std::uint32_t meet = grow(i);  // arc from the source tree to the sink tree
      ++time_;
      if (meet == kFreeNode) {
        current = kFreeNode;
        continue;
      }
      node_[i].next = i;  // keep i out of the queue: it is scanned again next round
      current = i;
      augment(meet);
      adopt();
    }
    return flow_;
  }

  bool source_side(std::uint32_t i) const { return node_[i].parent != kFreeNode && !node_[i].sink; }

 private:
  // Augments every path source -> i -> j -> sink of one arc, node by node: the bulk of the
  // flow in graphs where most nodes have a terminal capacity, without building trees.
  void push_short_paths() {
    for (std::uint32_t i = 0; i < n_; ++i) {
      if (g_.terminal[i] <= 0) continue;
      for (std::uint32_t a = g_.first[i], e = g_.first[i + 1]; a < e; ++a) {
        const std::uint32_t j = g_.head[a];
        if (g_.terminal[j] >= 0 || g_.cap[a] <= 0) continue;
        const double b = std::min({g_.terminal[i], -g_.terminal[j], g_.cap[a]});
        g_.terminal[i] -= b;
        g_.terminal[j] += b;
        g_.cap[a] -= b;
        g_.cap[g_.sister[a]] += b;
        flow_ += b;
        if (g_.terminal[i] <= 0) break;
      }
    }
  }

  void activate(std::uint32_t i) {
    if (node_[i].next != kFreeNode) return;
    node_[i].next = i;
    if (q_last_ == kFreeNode)
      q_first_ = i;
    else
      node_[q_last_].next = i;
    q_last_ = i;
  }

  std::uint32_t pop_active() {
    for (;;) {
      const std::uint32_t i = q_first_;
      if (i == kFreeNode) return kFreeNode;
      if (node_[i].next == i) {
        q_first_ = q_last_ = kFreeNode;
      } else {
        q_first_ = node_[i].next;
      }
      node_[i].next = kFreeNode;
      if (node_[i].parent != kFreeNode) return i;
    }
  }

  // Scans the residual arcs of active node i: free neighbours join i's tree; returns the
  // arc (oriented from the source tree to the sink tree) where the trees meet, if any.
  std::uint32_t grow(std::uint32_t i) {
    const Node& ni = node_[i];
    const bool sink = ni.sink;
    for (std::uint32_t a = g_.first[i], e = g_.first[i + 1]; a < e; ++a) {
      const std::uint32_t s = g_.sister[a];
      if ((sink ? g_.cap[s] : g_.cap[a]) <= 0) continue;  // residual i->j (source) or j->i (sink)
      const std::uint32_t j = g_.head[a];
      Node& nj = node_[j];
      if (nj.parent == kFreeNode) {
        nj.sink = sink;
        nj.parent = s;
        nj.stamp = ni.stamp;
        nj.dist = ni.dist + 1;
        activate(j);
      } else if (nj.sink != sink) {
        return sink ? s : a;
      } else if (nj.stamp <= ni.stamp && nj.dist > ni.dist) {
        // a shorter way to the terminal
        nj.parent = s;
        nj.stamp = ni.stamp;
        nj.dist = ni.dist + 1;
      }
    }
    return kFreeNode;
  }

  void make_orphan(std::uint32_t i) {
    node_[i].parent = kOrphan;
    orphans_.push_back(i);
  }

  // Pushes the bottleneck capacity along source -> ... -> tail(a) -> head(a) -> ... -> sink.
  void augment(std::uint32_t a) {
    const std::uint32_t i = g_.head[g_.sister[a]], j = g_.head[a];
    double b = g_.cap[a];
    for (std::uint32_t v = i;;) {
      const std::uint32_t p = node_[v].parent;
      if (p == kTerminal) {
        b = std::min(b, g_.terminal[v]);
        break;
      }
      b = std::min(b, g_.cap[g_.sister[p]]);  // residual parent -> v
      v = g_.head[p];
    }
    for (std::uint32_t v = j;;) {
      const std::uint32_t p = node_[v].parent;
      if (p == kTerminal) {
        b = std::min(b, -g_.terminal[v]);
        break;
      }
      b = std::min(b, g_.cap[p]);  // residual v -> parent
      v = g_.head[p];
    }
    g_.cap[g_.sister[a]] += b;
    g_.cap[a] -= b;
    for (std::uint32_t v = i;;) {
      const std::uint32_t p = node_[v].parent;
      if (p == kTerminal) {
        g_.terminal[v] -= b;
        if (g_.terminal[v] == 0) make_orphan(v);
        break;
      }
      const std::uint32_t s = g_.sister[p];
      g_.cap[p] += b;
      g_.cap[s] -= b;
      if (g_.cap[s] == 0) make_orphan(v);
      v = g_.head[p];
    }
    for (std::uint32_t v = j;;) {
      const std::uint32_t p = node_[v].parent;
      if (p == kTerminal) {
        g_.terminal[v] += b;
        if (g_.terminal[v] == 0) make_orphan(v);
        break;
      }
      g_.cap[g_.sister[p]] += b;
      g_.cap[p] -= b;
      if (g_.cap[p] == 0) make_orphan(v);
      v = g_.head[p];
    }
    flow_ += b;
  }

  // Arcs from node j to its terminal along the tree, or kNoDist when j's path meets an
  // orphan. Marks the nodes on the path with their distance for this round.
  std::uint32_t origin_dist(std::uint32_t j) {
    std::uint32_t steps = 0, d = kNoDist;
    for (std::uint32_t v = j;; ++steps) {
      const Node& nv = node_[v];
      if (nv.stamp == time_) {
        d = steps + nv.dist;
        break;
      }
      if (nv.parent == kTerminal) {
        d = steps + 1;
        break;
      }
      if (nv.parent == kOrphan || nv.parent == kFreeNode) return kNoDist;
      v = g_.head[nv.parent];
    }
    std::uint32_t dv = d;
    for (std::uint32_t v = j; node_[v].stamp != time_; v = g_.head[node_[v].parent]) {
      node_[v].stamp = time_;
      node_[v].dist = dv--;
      if (node_[v].parent == kTerminal) break;
    }
    return d;
  }

  void adopt() {
    for (std::size_t k = 0; k < orphans_.size(); ++k) {
      const std::uint32_t i = orphans_[k];
      const bool sink = node_[i].sink;
      // a new parent: a neighbour in the same tree with residual capacity towards i (source
      // tree) or from i (sink tree) whose own path reaches the terminal; the nearest
      std::uint32_t best = kFreeNode, best_d = kNoDist;
      for (std::uint32_t a = g_.first[i], e = g_.first[i + 1]; a < e; ++a) {
        const std::uint32_t j = g_.head[a];
        const Node& nj = node_[j];
        if (nj.parent == kFreeNode || nj.sink != sink) continue;
        if ((sink ? g_.cap[a] : g_.cap[g_.sister[a]]) <= 0) continue;
        const std::uint32_t d = origin_dist(j);
        if (d < best_d) best = a, best_d = d;
      }
      if (best != kFreeNode) {
        node_[i].parent = best;
        node_[i].stamp = time_;
        node_[i].dist = best_d + 1;
        continue;
      }
      // none: i leaves the tree; its children become orphans, and the neighbours that
      // could reach it again become active
      node_[i].parent = kFreeNode;
      for (std::uint32_t a = g_.first[i], e = g_.first[i + 1]; a < e; ++a) {
        const std::uint32_t j = g_.head[a];
        Node& nj = node_[j];
        if (nj.parent == kFreeNode || nj.sink != sink) continue;
        if ((sink ? g_.cap[a] : g_.cap[g_.sister[a]]) > 0) activate(j);
        if (nj.parent != kTerminal && nj.parent != kOrphan && g_.head[nj.parent] == i) make_orphan(j);
      }
    }
    orphans_.clear();
  }

  FlowGraph& g_;
  std::uint32_t n_;
  std::vector<Node> node_;
  std::vector<std::uint32_t> orphans_;
  std::uint32_t q_first_ = kFreeNode, q_last_ = kFreeNode;
  std::uint32_t time_ = 1;
  double flow_ = 0;
};

}  // namespace

std::int64_t FlowGraph::bytes() const {
  return static_cast<std::int64_t>(first.size() * sizeof(std::uint32_t) +
                                   head.size() * (2 * sizeof(std::uint32_t) + sizeof(double)) +
                                   terminal.size() * (sizeof(double) + sizeof(Node)));
}

double max_flow(FlowGraph& g, std::vector<std::uint8_t>& source_side) {
  const std::uint32_t n = g.nodes();
  require(g.terminal.size() == n, "max_flow: one terminal capacity per node expected");
  require(g.sister.size() == g.head.size() && g.cap.size() == g.head.size() && (n == 0 || g.first[n] == g.head.size()),
          "max_flow: inconsistent arc arrays");
  require(g.head.size() < kOrphan, "max_flow: too many arcs (", g.head.size(), ")");
  Solver s(g);
  const double flow = s.run();
  source_side.assign(n, 0);
  for (std::uint32_t i = 0; i < n; ++i) source_side[i] = s.source_side(i);
  return flow;
}

}  // namespace tetmvs::cut
