// Options of the photoconsist stage (paper sections 2.3 and 3.1, docs/photoconsist.md):
// the measure's options for lattice points (PointMeasure) and for face scores (mu x mu
// grid), the lattice density, the visual-hull margin and the crossing-face rule.
// Validated up front by check().
#pragma once
#include <array>
#include <cstdint>
#include <string>

#include "common/param_binding.h"
#include "common/photo/options.h"
#include "common/photoconsist/occlusion.h"
#include "common/q_silhouettes.h"

namespace tetmvs {
class Params;

namespace photoconsist {

// The crossing-face rule: a face with N lattice points inside the visual hull, c of them
// photo-consistent, is crossing when
//   c >= min_points_abs  and  c >= combine(ceil(fraction * N), points)
// where combine is min ("min" rule: the reading of the paper's sentence that works on large
// coarse faces) or max ("max" rule). See docs/photoconsist.md for the measurements.
struct CrossingRule {
  double fraction = 0;         // photo.cross_fraction
  int points = 20;             // photo.cross_points
  std::string combine = "min"; // photo.cross_rule: "min" or "max"
  int min_points_abs = 1;      // photo.cross_min
  // Consistent points needed on a face with n_samples points inside the hull (>= 1).
  std::int64_t needed(std::int64_t n_samples) const;
  bool crossing(std::int64_t consistent, std::int64_t n_samples) const {
    return n_samples > 0 && consistent >= needed(n_samples);
  }
  void check() const;  // throws Error on a value outside its documented range

  static constexpr auto params() {  // the fields that hold parameters (common/param_binding.h)
    return std::to_array<ParamField<CrossingRule>>({
        {"photo.cross_fraction", &CrossingRule::fraction},
        {"photo.cross_points", &CrossingRule::points},
        {"photo.cross_rule", &CrossingRule::combine},
        {"photo.cross_min", &CrossingRule::min_points_abs},
    });
  }
};

// The measure at the lattice points: the face scores' measure (photo.*) with its own patch,
// cameras, partners and de-trending. Read from the parameters and turned into
// Options::line by from_params.
struct PointMeasure {
  std::string patch = "grid";  // photo.point_patch: "grid" (grid_mu x grid_mu on each orientation's plane) or "line" (1 x line_mu)
  int line_mu = 21;            // photo.line_mu
  int grid_mu = 7;             // photo.point_grid_mu
  int k = 8;                   // photo.point_k: cameras per patch (0: photo.k)
  int partners = 6;            // photo.point_partners: k' (0: max(k/2, 3))
  bool detrend = true;         // photo.point_detrend
  bool outline_fill = true;    // photo.point_outline_fill (photo::Options::outline_fill)
  // `face` with the above, scoring with fewer than k views when fewer are usable (adaptive_k).
  photo::Options applied_to(const photo::Options& face) const;
  void check() const;  // throws Error on a value outside its documented range
  // check(), and partners at most the patch's cameras - 1 (point_k, or with point_k = 0
  // face.k): the Error names photo.point_partners and photo.point_k.
  void check_with(const photo::Options& face) const;

  static constexpr auto params() {  // the fields that hold parameters (common/param_binding.h)
    return std::to_array<ParamField<PointMeasure>>({
        {"photo.point_patch", &PointMeasure::patch},
        {"photo.line_mu", &PointMeasure::line_mu},
        {"photo.point_grid_mu", &PointMeasure::grid_mu},
        {"photo.point_k", &PointMeasure::k},
        {"photo.point_partners", &PointMeasure::partners},
        {"photo.point_detrend", &PointMeasure::detrend},
        {"photo.point_outline_fill", &PointMeasure::outline_fill},
    });
  }
};

struct Options {
  photo::Options line;        // lattice points: `face` changed by the PointMeasure (from_params)
  photo::Options face;        // face scores: photo.* (the mu x mu grid)
  double lattice_px = 2;      // photo.lattice_px: max projected spacing of lattice points (pixels of the level's scale)
  bool orientation_prior = true;  // photo.orientation_prior: orientations near the previous level's Q (level_pass.h)
  double level_cell_px = 4;   // photo.level_cell_px: image-pyramid level per mesh level (level_scale.h); 0 = full images
  double hull_margin_px = 2;  // photo.hull_margin_px: silhouettes dilated by this for the hull test
  double hull_core_px = 0;    // label.hull_core_px: lattice points this deep in every silhouette are skipped
  // photo.sight_views, photo.sight_margin_px: from level 1 on, crossing faces in the air that
  // the cameras of Q saw through are not crossing (sight_lines.h); 0 views = off.
  int sight_views = 16;
  double sight_margin_px = 28;
  // photo.q_hull*: in a scene without any silhouette, from level 1 on (and for the face
  // scores) the hull test uses silhouettes estimated from Q of the previous levels
  // (common/q_silhouettes.h, shared with label), grown by q_sil.margin_px (docs/colmap.md).
  QSilhouetteOptions q_sil;
  CrossingRule rule;
  OcclusionOptions occl;      // photo.occlusion, photo.occl_*: occlusion-aware camera selection (level >= 1)
  // Throws Error on a bad value: the documented ranges of every part, line's and face's rules.
  void check() const;
  static Options from_params(const Params& p);
  // Values that must agree between a cache and the run reusing it.
  std::string cache_signature() const;

  static constexpr auto params() {  // the fields that hold parameters (common/param_binding.h)
    return std::to_array<ParamField<Options>>({
        {"photo.lattice_px", &Options::lattice_px},
        {"photo.orientation_prior", &Options::orientation_prior},
        {"photo.level_cell_px", &Options::level_cell_px},
        {"photo.hull_margin_px", &Options::hull_margin_px},
        {"label.hull_core_px", &Options::hull_core_px},
        {"photo.sight_views", &Options::sight_views},
        {"photo.sight_margin_px", &Options::sight_margin_px},
    });
  }
};

}  // namespace photoconsist
}  // namespace tetmvs
