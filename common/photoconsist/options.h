// Options of the photoconsist stage (paper sections 2.3 and 3.1, docs/photoconsist.md):
// the measure's options for lattice points (1 x line_mu line) and for face scores
// (mu x mu grid), the lattice density, the visual-hull margin and the crossing-face rule.
// Validated up front by check().
#pragma once
#include <cstdint>
#include <string>

#include "common/photo/options.h"
#include "common/photoconsist/occlusion.h"

namespace tetmvs {
class Params;

namespace photoconsist {

// The crossing-face rule: a face with N lattice points inside the visual hull, c of them
// photo-consistent, is crossing when
//   c >= min_points_abs  and  c >= combine(ceil(fraction * N), points)
// where combine is min ("min" rule: the reading of the paper's sentence that works on large
// coarse faces) or max ("max" rule). See docs/photoconsist.md for the measurements.
struct CrossingRule {
  double fraction = 0.2;  // photo.cross_fraction
  int points = 20;        // photo.cross_points
  bool use_max = false;   // photo.cross_rule == "max"
  int min_points_abs = 1; // photo.cross_min
  // Consistent points needed on a face with n_samples points inside the hull (>= 1).
  std::int64_t needed(std::int64_t n_samples) const;
  bool crossing(std::int64_t consistent, std::int64_t n_samples) const {
    return n_samples > 0 && consistent >= needed(n_samples);
  }
  void check() const;
};

struct Options {
  photo::Options line;        // lattice points: mu = photo.line_mu, k = photo.point_k (0: photo.k)
  photo::Options face;        // face scores: mu = photo.mu (the mu x mu grid)
  double lattice_px = 1.0;    // photo.lattice_px: max projected spacing of lattice points (pixels of the level's scale)
  bool orientation_prior = false;  // photo.orientation_prior: orientations near the previous level's Q (level_pass.h)
  double level_cell_px = 0;   // photo.level_cell_px: image-pyramid level per mesh level (level_scale.h); 0 = full images
  double hull_margin_px = 2;  // photo.hull_margin_px: silhouettes dilated by this for the hull test
  double hull_core_px = 0;    // label.hull_core_px: lattice points this deep in every silhouette are skipped
  // photo.q_hull*: in a scene without any silhouette, from level 1 on (and for the face
  // scores) the hull test uses silhouettes estimated from Q of the previous levels
  // (common/q_silhouettes.h, shared with label), grown by q_hull_margin_px (docs/colmap.md).
  bool q_hull = true;
  double q_hull_splat_cells = 0.5;   // splat radius, in cells of the latest level of Q
  double q_hull_close_cells = 1.0;   // closing radius, in those cells (projected at Q's median depth) ...
  double q_hull_close_px = 6;        // ... and at least this many pixels
  double q_hull_margin_px = 4;
  int q_hull_min_points = 50;
  CrossingRule rule;
  OcclusionOptions occl;      // photo.occlusion, photo.occl_*: occlusion-aware camera selection (level >= 1)
  void check() const;
  static Options from_params(const Params& p);
  // Values that must agree between a cache and the run reusing it.
  std::string cache_signature() const;
};

}  // namespace photoconsist
}  // namespace tetmvs
