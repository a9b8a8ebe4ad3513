#include "common/photo/ncc.h"

#include "common/error.h"

namespace tetmvs::photo {

float ncc(const float* a, const float* b, int n, float min_std) {
  require(n >= 2 && n <= 1024, "photo::ncc: patch size ", n, " must be in [2, 1024]");
  float na[1024], nb[1024];
  normalize_patch(a, n, min_std, na);
  normalize_patch(b, n, min_std, nb);
  return ncc_normalized(na, nb, n);
}

}  // namespace tetmvs::photo
