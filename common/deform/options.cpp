#include "common/deform/options.h"

#include <algorithm>

#include "common/error.h"

namespace tetmvs::deform {

void Options::check() const {
  check_param_ranges(*this);
  require(photo_window % 2 == 1, "deform options: photo_window = ", photo_window, " must be odd");
  require(photo_baseline_min_deg <= photo_baseline_max_deg, "deform options: photo baselines ", photo_baseline_min_deg,
          "..", photo_baseline_max_deg, " degrees must satisfy min <= max");
  require(max_edge_px > 2 * min_edge_px, "deform options: max_edge_px = ", max_edge_px,
          " must exceed 2 * min_edge_px = ", 2 * min_edge_px, " (a split edge must not be collapsed again)");
}

Options Options::from_params(const Params& p) {
  Options o;
  read_params(p, o);
  o.check();
  return o;
}

int Options::photo_level(int it) const {
  if (it < photo_start) return -1;
  return std::max(0, photo_coarsest_level - (it - photo_start) / photo_level_iterations);
}

int Options::mesh_level(int it) const {
  if (it >= iterations) return 0;
  return it < photo_start ? photo_coarsest_level : photo_level(it);
}

}  // namespace tetmvs::deform
