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
  std::array<int, kMaxK> partners{};  // the reference's best k' partner views, best NCC first
  std::array<float, kMaxK> partner_ncc{};  // their NCCs with the reference
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
// The affine projection of a grid patch (sample_grid in patch.cpp): centre (u0, v0) and the
// image steps of its two axes, from the homogeneous centre h0 (h0.z > 0) and the
// homogeneous images b1, b2 of one world step along each axis.
struct GridAxes {
  double u0, v0, du1, dv1, du2, dv2;
};
inline GridAxes grid_axes(const Eigen::Vector3d& h0, const Eigen::Vector3d& b1, const Eigen::Vector3d& b2) {
  const double iw = 1.0 / h0.z();
  GridAxes g;
  g.u0 = h0.x() * iw;
  g.v0 = h0.y() * iw;
  g.du1 = (b1.x() - g.u0 * b1.z()) * iw;
  g.dv1 = (b1.y() - g.v0 * b1.z()) * iw;
  g.du2 = (b2.x() - g.u0 * b2.z()) * iw;
  g.dv2 = (b2.y() - g.v0 * b2.z()) * iw;
  return g;
}
// After prepare_centre(X): scores the patch of unit normal n with unit in-plane axis a1
// (line) or axes a1, a2 (grid, when a2 != nullptr).
void score_prepared(const Views& views, const Eigen::Vector3d& n, const Eigen::Vector3d& a1,
                    const Eigen::Vector3d* a2, const Options& opts, Scratch& s, PatchResult& out);
// The patch at X with axes a1 (and a2 for a grid) and sample spacing `spacing`, scored in
// exactly the `count` views of view_list (in that order) with kp partners; invalid when
// a sample of some view leaves its image (or count < 2, kp outside [1, count - 1]).
void score_in_views(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& a1,
                    const Eigen::Vector3d* a2, double spacing, const int* view_list, int count, int kp,
                    const Options& opts, Scratch& s, PatchResult& out);
}  // namespace detail

// The views that see what the reference view `ref` sees at X: among the (at most
// max_views, <= kMaxK) candidates nearest in angle to the unit normal n within the cone
// (camera_select.h, after prepare_centre-like selection at X), those whose patch (axes
// a1, a2 as for score_in_views, sample spacing `spacing`) has an NCC with ref's patch above
// min_ncc. Writes their ids to out (best NCC first, ties by view id) and returns their
// count; ref itself is not listed. A point of Q is visible in these views.
int agreeing_views(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& n, const Eigen::Vector3d& a1,
                   const Eigen::Vector3d* a2, double spacing, int ref, double min_ncc, int max_views,
                   const Options& opts, Scratch& scratch, int* out);

}  // namespace tetmvs::photo
