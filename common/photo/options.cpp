#include "common/photo/options.h"

#include <cmath>

#include "common/error.h"
#include "common/params.h"

namespace tetmvs::photo {

void Options::check() const {
  require(mu >= 3 && mu <= kMaxMu && mu % 2 == 1, "photo options: mu = ", mu,
          " must be odd and in [3, ", kMaxMu, "] (the patch is centred on its point)");
  require(k >= 4 && k <= kMaxK, "photo options: k = ", k, " must be in [4, ", kMaxK,
          "] (k' = max(k/2, 3) partners need k >= 4)");
  require(std::isfinite(cone_deg) && cone_deg > 0.0 && cone_deg < 90.0, "photo options: cone_deg = ",
          cone_deg, " must be in (0, 90) degrees");
  require(std::isfinite(T) && T > -1.0 && T < 1.0, "photo options: T = ", T,
          " must be in (-1, 1) (an NCC threshold)");
  require(std::isfinite(min_std) && min_std >= 0.0 && min_std < 1.0, "photo options: min_std = ",
          min_std, " must be in [0, 1) (grey levels are in [0, 1])");
  require(partners >= 0 && partners <= k - 1, "photo options: partners (k') = ", partners, " must lie in [0, k - 1 = ",
          k - 1, "] (0: max(k/2, 3))");
}

Options Options::from_params(const Params& p) {
  Options o;
  o.mu = p.i("photo.mu");
  o.k = p.i("photo.k");
  o.cone_deg = p.d("photo.cone_deg");
  o.T = p.d("photo.T");
  o.min_std = p.d("photo.min_std");
  o.use_silhouettes = p.b("photo.use_silhouettes");
  o.detrend = p.b("photo.detrend");
  o.check();
  return o;
}

}  // namespace tetmvs::photo
