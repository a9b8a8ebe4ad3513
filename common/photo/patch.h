// Photo-consistency of one oriented patch (paper sections 2.3 and 3.1, docs/photo.md).
//
// A patch is a set of mu (line) or mu x mu (grid) sample points on a plane through a
// 3-D centre X with unit normal n. The views: the best k candidates of
// camera_select.h whose every sample projects inside the image (others are dropped
// and the next candidate is tried). Sample spacing: one pixel footprint (depth /
// focal) at X in the finest of the first k candidates. Each view's samples are
// bilinear grey values, normalized (ncc.h); for each view as reference, its score is
// the mean of its best k' = max(k/2, 3) NCCs with the other views; the patch's score
// is the best reference's. Defined only with at least k'+1 usable views.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

#include "common/photo/options.h"
#include "common/photo/scratch.h"
#include "common/photo/views.h"

namespace tetmvs::photo {

// Score of a patch with too few usable views.
inline constexpr float kNoScore = -1.f;

struct PatchResult {
  float score = kNoScore;  // mean of the reference's best k' NCCs, in [-1, 1]; kNoScore if undefined
  int ref = -1;            // reference (best) view; -1 when undefined
  int num_partners = 0;    // k' when defined
  std::array<int, kMaxKPrime> partners{};  // the reference's best k' partner views, best NCC first
  int num_views = 0;       // usable views the NCCs were computed on (k'+1 .. k) when defined
  std::array<int, kMaxK> views{};  // those views, smallest angle first
  float spacing = 0;       // world distance between neighbouring samples (0 when no candidate)

  bool valid() const { return ref >= 0; }
  // The cut's omega: score truncated to [0, 1]; 0 when undefined.
  float omega() const { return valid() ? (score > 0.f ? (score < 1.f ? score : 1.f) : 0.f) : 0.f; }
};

// 1 x mu line patch (section 2.3) at X with patch normal nx, along nx x nf, nf the
// normal of the face the point lies on (a stable perpendicular of nf when nx || nf).
PatchResult score_line(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& nx,
                       const Eigen::Vector3d& nf, const Options& opts, Scratch& scratch);

// mu x mu grid patch (section 3.1) at X on the plane of normal n; in-plane axes
// stable_perpendicular(n) and n x that. The measure behind the cut's omega, the
// silhouette-fix ray profiles and deform's texture force. Invalid when n is zero.
PatchResult score_patch(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& n,
                        const Options& opts, Scratch& scratch);

namespace detail {
// After prepare_centre(X): scores the patch of unit normal n with unit in-plane axis a1
// (line) or axes a1, a2 (grid, when a2 != nullptr).
void score_prepared(const Views& views, const Eigen::Vector3d& n, const Eigen::Vector3d& a1,
                    const Eigen::Vector3d* a2, const Options& opts, Scratch& s, PatchResult& out);
}  // namespace detail

}  // namespace tetmvs::photo
