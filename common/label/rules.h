// The labelling rules of `label` and the one table that decides between them.
//
// Every rule proposes a set of cells (labels.cpp, one function per rule); a cell takes the
// label and reason of the first rule in kRules that proposes it, and stays free (the cut
// decides) when none does. The order of kRules is the precedence, written once here and in
// docs/architecture.md ("Labels"):
//
//   boundary > outside_hull > outside_q_hull   geometry: the box and the silhouettes are sure
//   > hull_core                                 an optional prior that overrules Q
//   > seen_free > voted_out > hidden            Q: free space outranks occlusion
//   > seed_core                                 the hull core, only when Q gave no interior cell
//
// voted_out (many votes) and hidden (few votes) never propose the same cell; seed_core
// proposes cells only when no rule above labels any cell interior.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "common/reason.h"

namespace tetmvs::label {

// In precedence order.
enum class Rule : std::uint8_t {
  kBoundary,      // exterior: touches the mesh boundary (paper 2.4)
  kOutsideHull,   // exterior: outside a silhouette (paper 2.4)
  kOutsideQHull,  // exterior: outside a silhouette estimated from Q (scenes without any)
  kHullCore,      // interior: deep inside every silhouette (Options::hull_core_px)
  kSeenFree,      // exterior: a cavity's air seen over its rim (Options::seen_free_views)
  kVotedOut,      // exterior: many votes and seen as free space (paper 2.4)
  kHidden,        // interior: few votes, hidden just behind Q (paper 2.4, with a depth limit)
  kSeedCore,      // interior: the hull core, when Q gave no interior cell
};
inline constexpr int kNumRules = 8;

struct RuleInfo {
  Rule rule;
  const char* name;  // its count's name in labels.h5 and the stage summary
  Reason reason;     // written to /cells/reason (kNone: the cell is left free)
  std::int8_t label;  // 1 interior, -1 exterior, 0 free
};

// The precedence table: kRules[i].rule == Rule(i).
inline constexpr std::array<RuleInfo, kNumRules> kRules = {{
    {Rule::kBoundary, "boundary", kBoundary, -1},
    {Rule::kOutsideHull, "outside_hull", kOutsideHull, -1},
    {Rule::kOutsideQHull, "outside_q_hull", kOutsideQHull, -1},
    {Rule::kHullCore, "hull_core", kHullCore, 1},
    {Rule::kSeenFree, "seen_free", kSeenFree, -1},
    {Rule::kVotedOut, "voted_out", kVotedOut, -1},
    {Rule::kHidden, "hidden", kHidden, 1},
    {Rule::kSeedCore, "seed_core", kSeedCore, 1},
}};

inline constexpr const RuleInfo& info(Rule r) { return kRules[static_cast<int>(r)]; }

// Per cell, bit r set when Rule r proposes the cell.
class Proposals {
 public:
  explicit Proposals(std::int32_t cells) : bits_(cells, 0) {}
  void add(Rule r, std::int32_t c) { bits_[c] |= static_cast<std::uint16_t>(1u << static_cast<int>(r)); }
  // every cell whose flag is non-zero
  void add(Rule r, const std::vector<std::uint8_t>& cells);
  bool has(Rule r, std::int32_t c) const { return bits_[c] >> static_cast<int>(r) & 1u; }
  // The rule that labels cell c: the first in kRules that proposes it; -1 when none does.
  int winner(std::int32_t c) const;
  std::int32_t size() const { return static_cast<std::int32_t>(bits_.size()); }

 private:
  std::vector<std::uint16_t> bits_;
};

struct Decision {
  std::vector<std::int8_t> label;    // per cell: 1 interior, -1 exterior, 0 free
  std::vector<std::uint8_t> reason;  // Reason
  std::vector<std::int8_t> rule;     // the winning rule (-1: none)
  std::array<std::int64_t, kNumRules> cells{};  // cells each rule labels (wins)
  std::int64_t interior = 0, exterior = 0;
};

// The precedence table applied to every cell.
Decision decide(const Proposals& p);

}  // namespace tetmvs::label
