// Options of the photo-consistency measure (paper sections 2.3 and 3.1), validated
// up front by check(). Defaults, ranges and meanings: params/defaults.json ("photo.*",
// bound in params()) and docs/photo.md.
#pragma once
#include <algorithm>
#include <array>

#include "common/param_binding.h"

namespace tetmvs {
class Params;

namespace photo {

// Upper bounds that size the fixed arrays of the results (no allocation per call).
inline constexpr int kMaxK = 16;
inline constexpr int kMaxKPrime = kMaxK - 1;
inline constexpr int kMaxMu = 31;

struct Options {
  int mu = 5;              // patch size in samples: 1 x mu line or mu x mu grid
  int k = 5;               // cameras used per patch (the best k within the cone)
  double cone_deg = 75.0;  // max angle between the patch normal and the direction to a camera
  double T = 0.6;          // a point is photo-consistent when its score > T (docs/photoconsist.md)
  double min_std = 1e-3;   // patches whose grey std is below this are "constant": NCC = 0
  bool use_silhouettes = false;  // drop a view when the patch centre is outside its silhouette
  // Remove each patch's least-squares linear ramp (per axis) before the NCC
  // (normalize_patch_detrended, ncc.h): shading gradients on untextured surfaces then
  // stop correlating perfectly off the surface. Off by default (the paper's measure).
  bool detrend = false;
  // score_point (oriented_point.h) scores a mu x mu grid on the plane of each
  // orientation instead of the paper's 1 x mu line on the face plane. Set by
  // photoconsist from photo.point_patch; off by default.
  bool point_grid = false;
  // When fewer than k views are usable, score with the m usable ones (k' = max(m/2, 3),
  // defined for m >= 4) instead of leaving the patch undefined below k'+1 views. Lets a
  // large k (wide baselines on dense rings) degrade gracefully on sparse camera sets.
  // Set by photoconsist for its lattice points (photo.point_k); off by default.
  bool adaptive_k = false;
  // Samples of a patch that fall outside a view's silhouette take the mean of the samples
  // inside it, and a view with fewer than half inside is not used: the outline's edge, which
  // neighbouring views see at nearly the same place, would otherwise correlate at depths
  // inside the surface. Set by photoconsist for its lattice points (photo.point_outline_fill);
  // off by default.
  bool outline_fill = false;

  // k' = max(k/2, 3): each camera's score is the mean of its best k' NCCs.
  // k', the partners whose NCCs make a reference's score: 0 is the paper's max(k/2, 3);
  // otherwise that many (at most k - 1; k - 1 makes every pair count, the widest baselines
  // included, which narrows the band of high scores around the surface: docs/photo.md).
  int partners = 0;

  int k_prime() const { return partners > 0 ? partners : std::max(k / 2, 3); }
  // Fewest usable cameras for a defined score: the reference plus k' partners.
  int min_cams() const { return k_prime() + 1; }
  // Fewest usable views for a defined score: k' + 1, or with adaptive_k at most 4.
  int min_views() const { return adaptive_k ? std::min(k_prime() + 1, 4) : k_prime() + 1; }
  // k' when `used` views (>= min_views()) are usable: with adaptive_k and fewer than k
  // views, max(used/2, 3) (the paper's rule) or, when partners is set, used - 1 minus as
  // many as k - 1 - partners (the same number of worst NCCs left out).
  int partners_for(int used) const {
    if (!adaptive_k || used >= k) return k_prime();
    // with partners set, as many of each reference's worst NCCs left out as with k views
    return partners > 0 ? std::max(1, used - 1 - (k - 1 - partners)) : std::max(used / 2, 3);
  }
  // Throws tetmvs::Error naming the bad value: the documented ranges, an odd mu, mu and k
  // within the arrays' bounds, partners <= k - 1.
  void check() const;
  // Reads the parameters params() binds, then check()s. photoconsist derives the lattice
  // points' options from these (photoconsist::PointMeasure).
  static Options from_params(const Params& p);

  static constexpr auto params() {
    return std::to_array<ParamField<Options>>({
        {"photo.mu", &Options::mu},
        {"photo.k", &Options::k},
        {"photo.cone_deg", &Options::cone_deg},
        {"photo.T", &Options::T},
        {"photo.min_std", &Options::min_std},
        {"photo.use_silhouettes", &Options::use_silhouettes},
        {"photo.detrend", &Options::detrend},
    });
  }
};

}  // namespace photo
}  // namespace tetmvs
