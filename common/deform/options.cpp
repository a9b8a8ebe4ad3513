#include "common/deform/options.h"

#include <cmath>

#include "common/error.h"
#include "common/params.h"

namespace tetmvs::deform {

void Options::check() const {
  const auto finite_in = [](double x, double lo, double hi) { return std::isfinite(x) && x >= lo && x <= hi; };
  require(iterations >= 0 && iterations <= 100000, "deform options: iterations = ", iterations, " must be in [0, 100000]");
  require(finite_in(smooth_tangent, 0, 1), "deform options: smooth_tangent = ", smooth_tangent, " must be in [0, 1]");
  require(finite_in(smooth_normal, 0, 1), "deform options: smooth_normal = ", smooth_normal, " must be in [0, 1]");
  require(finite_in(smooth_bilaplacian, 0, 0.49), "deform options: smooth_bilaplacian = ", smooth_bilaplacian,
          " must be in [0, 0.49] (explicit bi-Laplacian steps above 0.5 diverge)");
  require(finite_in(w_silhouette, 0, 1), "deform options: w_silhouette = ", w_silhouette, " must be in [0, 1]");
  require(finite_in(w_texture, 0, 1), "deform options: w_texture = ", w_texture, " must be in [0, 1]");
  require(finite_in(rim_cos, 0, 1), "deform options: rim_cos = ", rim_cos, " must be in [0, 1]");
  require(finite_in(sil_band_px, 0, 100), "deform options: sil_band_px = ", sil_band_px, " must be in [0, 100]");
  require(finite_in(sil_max_px, 0, 1000), "deform options: sil_max_px = ", sil_max_px, " must be in [0, 1000]");
  require(finite_in(visibility_tol_px, 0, 1e6), "deform options: visibility_tol_px = ", visibility_tol_px, " must be >= 0");
  require(finite_in(texture_step_px, 1e-3, 100), "deform options: texture_step_px = ", texture_step_px,
          " must be in [0.001, 100]");
  require(finite_in(texture_coarse_px, texture_step_px, 100), "deform options: texture_coarse_px = ", texture_coarse_px,
          " must be in [texture_step_px, 100]");
  require(finite_in(texture_range_px, texture_coarse_px, 100), "deform options: texture_range_px = ", texture_range_px,
          " must be in [texture_coarse_px, 100]");
  require(finite_in(texture_far_px, texture_range_px, 100), "deform options: texture_far_px = ", texture_far_px,
          " must be in [texture_range_px = ", texture_range_px, ", 100]");
  require(finite_in(texture_far_min_score, -1, 1), "deform options: texture_far_min_score = ", texture_far_min_score,
          " must be in [-1, 1]");
  require(finite_in(texture_far_min_contrast, 0, 2), "deform options: texture_far_min_contrast = ",
          texture_far_min_contrast, " must be in [0, 2]");
  require(texture_far_px / texture_coarse_px <= 200, "deform options: texture_far_px / texture_coarse_px = ",
          texture_far_px / texture_coarse_px, " offsets per side; at most 200");
  require(texture_range_px / texture_coarse_px <= 200, "deform options: texture_range_px / texture_coarse_px = ",
          texture_range_px / texture_coarse_px, " offsets per side; at most 200");
  require(finite_in(texture_min_score, -1, 1), "deform options: texture_min_score = ", texture_min_score, " must be in [-1, 1]");
  require(finite_in(texture_min_contrast, 0, 2), "deform options: texture_min_contrast = ", texture_min_contrast,
          " must be in [0, 2]");
  require(finite_in(texture_cone_deg, 1, 89), "deform options: texture_cone_deg = ", texture_cone_deg,
          " must be in [1, 89] degrees");
  require(texture_mu >= 3 && texture_mu <= 31 && texture_mu % 2 == 1, "deform options: texture_mu = ", texture_mu,
          " must be odd, in [3, 31]");
  require(texture_partners >= 1 && texture_partners <= 32, "deform options: texture_partners = ", texture_partners,
          " must be in [1, 32]");
  require(texture_min_partners >= 1 && texture_min_partners <= texture_partners,
          "deform options: texture_min_partners = ", texture_min_partners, " must be in [1, texture_partners = ",
          texture_partners, "]");
  require(finite_in(texture_baseline_min_deg, 0, 89) && finite_in(texture_baseline_max_deg, texture_baseline_min_deg, 90),
          "deform options: texture baselines ", texture_baseline_min_deg, "..", texture_baseline_max_deg,
          " degrees must satisfy 0 <= min <= max <= 90");
  require(finite_in(texture_settle_px, 0, 100), "deform options: texture_settle_px = ", texture_settle_px,
          " must be in [0, 100]");
  require(texture_recheck >= 1 && texture_recheck <= 1000, "deform options: texture_recheck = ", texture_recheck,
          " must be in [1, 1000]");
  require(texture_sag_rounds >= 0 && texture_sag_rounds <= 100, "deform options: texture_sag_rounds = ",
          texture_sag_rounds, " must be in [0, 100]");
  require(finite_in(texture_ring_weight, 0, 1), "deform options: texture_ring_weight = ", texture_ring_weight,
          " must be in [0, 1]");
  require(texture_start >= 0, "deform options: texture_start = ", texture_start, " must be >= 0");
  require(texture_pyramid >= 0 && texture_pyramid <= 4, "deform options: texture_pyramid = ", texture_pyramid,
          " must lie in [0, 4]");
  require(finite_in(max_move_px, 1e-6, 100), "deform options: max_move_px = ", max_move_px, " must be in (0, 100]");
  require(finite_in(min_edge_px, 0, 1e6) && finite_in(max_edge_px, 0, 1e6) && max_edge_px > 2 * min_edge_px,
          "deform options: max_edge_px = ", max_edge_px, " must exceed 2 * min_edge_px = ", 2 * min_edge_px,
          " (a split edge must not be collapsed again)");
  require(finite_in(needle_ratio, 0, 0.5), "deform options: needle_ratio = ", needle_ratio, " must be in [0, 0.5]");
  require(finite_in(flip_dihedral_deg, 0, 90), "deform options: flip_dihedral_deg = ", flip_dihedral_deg,
          " must be in [0, 90]");
  require(intersection_retries >= 0 && intersection_retries <= 20, "deform options: intersection_retries = ",
          intersection_retries, " must be in [0, 20]");
}

Options Options::from_params(const Params& p) {
  Options o;
  o.iterations = p.i("deform.iterations");
  o.smooth_tangent = p.d("deform.smooth_tangent");
  o.smooth_normal = p.d("deform.smooth_normal");
  o.smooth_bilaplacian = p.d("deform.smooth_bilaplacian");
  o.w_silhouette = p.d("deform.w_silhouette");
  o.rim_cos = p.d("deform.rim_cos");
  o.sil_band_px = p.d("deform.sil_band_px");
  o.sil_max_px = p.d("deform.sil_max_px");
  o.visibility_tol_px = p.d("deform.visibility_tol_px");
  o.w_texture = p.d("deform.w_texture");
  o.texture_range_px = p.d("deform.texture_range_px");
  o.texture_step_px = p.d("deform.texture_step_px");
  o.texture_far_px = p.d("deform.texture_far_px");
  o.texture_far_min_score = p.d("deform.texture_far_min_score");
  o.texture_far_min_contrast = p.d("deform.texture_far_min_contrast");
  o.texture_coarse_px = p.d("deform.texture_coarse_px");
  o.texture_min_score = p.d("deform.texture_min_score");
  o.texture_min_contrast = p.d("deform.texture_min_contrast");
  o.texture_cone_deg = p.d("deform.texture_cone_deg");
  o.texture_mu = p.i("deform.texture_mu");
  o.texture_partners = p.i("deform.texture_partners");
  o.texture_min_partners = p.i("deform.texture_min_partners");
  o.texture_baseline_min_deg = p.d("deform.texture_baseline_min_deg");
  o.texture_baseline_max_deg = p.d("deform.texture_baseline_max_deg");
  o.texture_settle_px = p.d("deform.texture_settle_px");
  o.texture_recheck = p.i("deform.texture_recheck");
  o.texture_start = p.i("deform.texture_start");
  o.texture_pyramid = p.i("deform.texture_pyramid");
  o.texture_ring_weight = p.d("deform.texture_ring_weight");
  o.texture_sag_rounds = p.i("deform.texture_sag_rounds");
  o.occlusion = p.b("deform.occlusion");
  o.max_move_px = p.d("deform.max_move_px");
  o.max_edge_px = p.d("deform.max_edge_px");
  o.min_edge_px = p.d("deform.min_edge_px");
  o.needle_ratio = p.d("deform.needle_ratio");
  o.flip_dihedral_deg = p.d("deform.flip_dihedral_deg");
  o.intersection_retries = p.i("deform.intersection_retries");
  o.check();
  return o;
}

int Options::texture_level(int it) const {
  const int n = iterations - texture_start;  // texture iterations
  const int k = it - texture_start;
  if (texture_pyramid <= 0 || n <= 1 || k < 0) return 0;
  const int coarse = n / 3;  // iterations on levels texture_pyramid .. 1
  if (k >= coarse) return 0;
  return texture_pyramid - (k * texture_pyramid) / coarse;
}

}  // namespace tetmvs::deform
