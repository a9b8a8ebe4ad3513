#include "common/photo/options.h"

#include "common/error.h"

namespace tetmvs::photo {

void Options::check() const {
  check_param_ranges(*this);
  require(mu % 2 == 1 && mu <= kMaxMu, "photo options: mu = ", mu, " must be odd and at most ", kMaxMu,
          " (the patch is centred on its point)");
  require(k <= kMaxK, "photo options: k = ", k, " must be at most ", kMaxK);
  require(partners >= 0 && partners <= k - 1, "photo options: partners (k') = ", partners, " must lie in [0, k - 1 = ",
          k - 1, "] (0: max(k/2, 3))");
}

Options Options::from_params(const Params& p) {
  Options o;
  read_params(p, o);
  o.check();
  return o;
}

}  // namespace tetmvs::photo
