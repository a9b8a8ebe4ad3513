// Why a cell carries a hard label: the codes of /cells/reason in labels.h5 and silfix.h5
// (schemas/labels.md). One code per labelling rule of `label` (common/label/rules.h, where
// their precedence is) and of `silhouette-fix`; the values are part of the file format.
#pragma once
#include <cstdint>

namespace tetmvs {

enum Reason : std::uint8_t {
  kNone = 0,            // free: the cut decides
  kBoundary = 1,        // exterior: touches the mesh boundary (paper 2.4)
  kOutsideHull = 2,     // exterior: outside a silhouette (paper 2.4)
  kVotedOut = 3,        // exterior: many visibility votes and seen as free space (paper 2.4)
  kHidden = 4,          // interior: few votes, hidden behind Q (paper 2.4, with a depth limit)
  kSilfixExterior = 5,  // exterior: silhouette-fix, the first surface too big (paper 3.2)
  kSilfixInterior = 6,  // interior: silhouette-fix, the first surface too small (paper 3.2)
  kHullCore = 7,        // interior: deep inside every silhouette (the optional hull-core prior)
  kOutsideQHull = 8,    // exterior: outside a silhouette estimated from Q (scenes without any)
  kSeedCore = 9,        // interior: the hull core, when Q gave no interior cell
  kSeenFree = 10,       // exterior: a cavity's air seen over its rim
};
inline constexpr int kNumReasons = 11;

// "boundary", "outside_hull", ... ("unknown" for a code out of range).
const char* reason_name(int reason);
// The label a reason gives: 1 interior, -1 exterior, 0 none (and for unknown codes).
int reason_label(int reason);

}  // namespace tetmvs
