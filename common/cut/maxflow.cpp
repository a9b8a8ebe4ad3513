#include "common/cut/maxflow.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace tetmvs::cut {

namespace {

// parent of a node: an arc index (the arc from the node to its parent), or one of these
constexpr std::uint32_t kFreeNode = 0xFFFFFFFFu;  // in no tree
constexpr std::uint32_t kTerminal = 0xFFFFFFFEu;  // child of the source or the sink
constexpr std::uint32_t kOrphan = 0xFFFFFFFDu;    // lost its parent arc, being re-attached
constexpr std::uint32_t kNoLabel = 0x7FFFFFFFu;

struct Node {
  std::uint32_t parent = kFreeNode;
  std::uint32_t next = kFreeNode;  // next in the active queue; itself when last; kFreeNode when not queued
  std::uint32_t label : 31 = 0;    // depth: 1 for a terminal's child, above its parent's otherwise
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
      node_[i].label = 1;
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
      reached_[node_[i].sink] = node_[i].label;
      const std::uint32_t meet = grow(i);  // arc from the source tree to the sink tree
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
        nj.label = ni.label + 1;
        activate(j);
      } else if (nj.sink != sink) {
        return sink ? s : a;
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

  // Arc a from i to j has a residual reverse arc j -> i (source tree) or is residual itself
  // (sink tree): j could be i's parent.
  bool feeds(std::uint32_t a, bool sink) const {
    return (sink ? g_.cap[a] : g_.cap[g_.sister[a]]) > 0;
  }

  // Finds each orphan a new parent. Labels only grow along a path from the terminal, so a
  // parent with a smaller label can never be a descendant: an orphan takes the neighbour in
  // its tree with the smallest label below its own (which may itself be an orphan not yet
  // handled: if that one moves, this one is orphaned again). Without one, the orphan is
  // relabelled under the smallest-labelled neighbour that is not an orphan, if that depth has
  // already been reached by the growth; its children that are no deeper become orphans.
  // Otherwise it leaves the tree: its children become orphans, and its neighbours that could
  // reach it again become active. (The relabelling stops at the growth's depth so that a part
  // cut off from the terminal empties at once instead of relabelling itself deeper and deeper.)
  void adopt() {
    for (std::size_t k = 0; k < orphans_.size(); ++k) {
      const std::uint32_t i = orphans_[k];
      Node& ni = node_[i];
      const bool sink = ni.sink;
      if (sink ? g_.terminal[i] < 0 : g_.terminal[i] > 0) {  // (a node with terminal capacity left is its child)
        ni.parent = kTerminal;
        ni.label = 1;
        continue;
      }
      std::uint32_t nearer = kFreeNode, nearer_label = ni.label;
      std::uint32_t any = kFreeNode, any_label = kNoLabel;  // not an orphan
      for (std::uint32_t a = g_.first[i], e = g_.first[i + 1]; a < e; ++a) {
        const Node& nj = node_[g_.head[a]];
        if (nj.parent == kFreeNode || nj.sink != sink || !feeds(a, sink)) continue;
        if (nj.label < nearer_label) nearer = a, nearer_label = nj.label;
        if (nj.parent != kOrphan && nj.label < any_label) any = a, any_label = nj.label;
      }
      if (nearer != kFreeNode) {
        ni.parent = nearer;
        continue;
      }
      if (any != kFreeNode && any_label + 1 <= reached_[sink]) {
        ni.parent = any;
        ni.label = any_label + 1;
        orphan_children(i, sink, ni.label);
        continue;
      }
      orphan_children(i, sink, kNoLabel);
      ni.parent = kFreeNode;
      for (std::uint32_t a = g_.first[i], e = g_.first[i + 1]; a < e; ++a) {
        const std::uint32_t j = g_.head[a];
        const Node& nj = node_[j];
        if (nj.parent != kFreeNode && nj.sink == sink && feeds(a, sink)) activate(j);
      }
    }
    orphans_.clear();
  }

  // Orphans the children of i whose label is at most `upto`.
  void orphan_children(std::uint32_t i, bool sink, std::uint32_t upto) {
    for (std::uint32_t a = g_.first[i], e = g_.first[i + 1]; a < e; ++a) {
      const std::uint32_t j = g_.head[a];
      const Node& nj = node_[j];
      if (nj.parent == kFreeNode || nj.parent == kTerminal || nj.parent == kOrphan || nj.sink != sink) continue;
      if (g_.head[nj.parent] == i && nj.label <= upto) make_orphan(j);
    }
  }

  FlowGraph& g_;
  std::uint32_t n_;
  std::vector<Node> node_;
  std::vector<std::uint32_t> orphans_;
  std::uint32_t q_first_ = kFreeNode, q_last_ = kFreeNode;
  std::uint32_t reached_[2] = {1, 1};  // label of the node last grown from, per tree
  double flow_ = 0;
};

}  // namespace

std::int64_t FlowGraph::bytes() const {
  return static_cast<std::int64_t>(first.size() * sizeof(std::uint32_t) +
                                   head.size() * (2 * sizeof(std::uint32_t) + sizeof(double)) +
                                   terminal.size() * (sizeof(double) + sizeof(Node)));
}

namespace {

// A residual below this share of a typical capacity is rounding left by the augmentations
// (the order in which they subtract decides whether it is exactly 0 or 1e-16 of a capacity).
constexpr double kRoundingShare = 1e-9;

// The median of up to 4096 positive arc capacities taken at a fixed stride (the terminal
// capacities when there is no arc); 0 when there is none.
double typical_capacity(const FlowGraph& g) {
  std::vector<double> sample;
  const auto take = [&](const std::vector<double>& x, bool magnitude) {
    const std::size_t stride = std::max<std::size_t>(1, x.size() / 4096);
    for (std::size_t k = 0; k < x.size(); k += stride) {
      const double c = magnitude ? std::abs(x[k]) : x[k];
      if (c > 0) sample.push_back(c);
    }
  };
  take(g.cap, false);
  if (sample.empty()) take(g.terminal, true);
  if (sample.empty()) return 0;
  std::nth_element(sample.begin(), sample.begin() + static_cast<std::ptrdiff_t>(sample.size() / 2), sample.end());
  return sample[sample.size() / 2];
}

}  // namespace

double max_flow(FlowGraph& g, std::vector<std::uint8_t>& source_side) {
  const std::uint32_t n = g.nodes();
  require(g.terminal.size() == n, "max_flow: one terminal capacity per node expected");
  require(g.sister.size() == g.head.size() && g.cap.size() == g.head.size() && (n == 0 || g.first[n] == g.head.size()),
          "max_flow: inconsistent arc arrays");
  require(g.head.size() < kOrphan, "max_flow: too many arcs (", g.head.size(), ")");
  const double tolerance = kRoundingShare * typical_capacity(g);
  double flow = 0;
  {
    Solver s(g);
    flow = s.run();
  }
  // the nodes reachable from the source over residual capacities above the rounding
  source_side.assign(n, 0);
  std::vector<std::uint32_t> queue;
  for (std::uint32_t i = 0; i < n; ++i)
    if (g.terminal[i] > tolerance) source_side[i] = 1, queue.push_back(i);
  for (std::size_t k = 0; k < queue.size(); ++k) {
    const std::uint32_t i = queue[k];
    for (std::uint32_t a = g.first[i], e = g.first[i + 1]; a < e; ++a) {
      const std::uint32_t j = g.head[a];
      if (!source_side[j] && g.cap[a] > tolerance) source_side[j] = 1, queue.push_back(j);
    }
  }
  return flow;
}

}  // namespace tetmvs::cut
