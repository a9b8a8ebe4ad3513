#include "common/deform/options.h"

#include <algorithm>
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
  require(finite_in(sil_tolerance_px, 0, 100), "deform options: sil_tolerance_px = ", sil_tolerance_px,
          " must be in [0, 100]");
  require(finite_in(w_photo, 0, 1), "deform options: w_photo = ", w_photo, " must be in [0, 1]");
  require(photo_start >= 0, "deform options: photo_start = ", photo_start, " must be >= 0");
  require(photo_window >= 3 && photo_window <= 31 && photo_window % 2 == 1, "deform options: photo_window = ",
          photo_window, " must be odd, in [3, 31]");
  require(photo_partners >= 1 && photo_partners <= 32, "deform options: photo_partners = ", photo_partners,
          " must be in [1, 32]");
  require(finite_in(photo_baseline_min_deg, 0, 89) && finite_in(photo_baseline_max_deg, photo_baseline_min_deg, 90),
          "deform options: photo baselines ", photo_baseline_min_deg, "..", photo_baseline_max_deg,
          " degrees must satisfy 0 <= min <= max <= 90");
  require(photo_coarsest_level >= 0 && photo_coarsest_level <= 6, "deform options: photo_coarsest_level = ",
          photo_coarsest_level, " must lie in [0, 6]");
  require(photo_level_iterations >= 1 && photo_level_iterations <= 100, "deform options: photo_level_iterations = ",
          photo_level_iterations, " must lie in [1, 100]");
  require(finite_in(rim_cos, 0, 1), "deform options: rim_cos = ", rim_cos, " must be in [0, 1]");
  require(finite_in(sil_band_px, 0, 100), "deform options: sil_band_px = ", sil_band_px, " must be in [0, 100]");
  require(finite_in(sil_max_px, 0, 1000), "deform options: sil_max_px = ", sil_max_px, " must be in [0, 1000]");
  require(finite_in(visibility_tol_px, 0, 1e6), "deform options: visibility_tol_px = ", visibility_tol_px, " must be >= 0");
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
  o.sil_tolerance_px = p.d("deform.sil_tolerance_px");
  o.w_photo = p.d("deform.w_photo");
  o.photo_start = p.i("deform.photo_start");
  o.photo_window = p.i("deform.photo_window");
  o.photo_partners = p.i("deform.photo_partners");
  o.photo_baseline_min_deg = p.d("deform.photo_baseline_min_deg");
  o.photo_baseline_max_deg = p.d("deform.photo_baseline_max_deg");
  o.photo_coarsest_level = p.i("deform.photo_coarsest_level");
  o.photo_level_iterations = p.i("deform.photo_level_iterations");
  o.max_move_px = p.d("deform.max_move_px");
  o.max_edge_px = p.d("deform.max_edge_px");
  o.min_edge_px = p.d("deform.min_edge_px");
  o.needle_ratio = p.d("deform.needle_ratio");
  o.flip_dihedral_deg = p.d("deform.flip_dihedral_deg");
  o.intersection_retries = p.i("deform.intersection_retries");
  o.check();
  return o;
}

int Options::photo_level(int it) const {
  if (it < photo_start) return -1;
  return std::max(0, photo_coarsest_level - (it - photo_start) / photo_level_iterations);
}

}  // namespace tetmvs::deform
