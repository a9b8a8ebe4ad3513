// Normalized cross-correlation (NCC) of image patches: the kernel of the
// photo-consistency measure (paper sections 2.3 and 3.1, docs/photo.md).
//
// NCC(a, b) = sum (a_i - mean a)(b_i - mean b) / sqrt(sum (a_i - mean a)^2 sum (b_i - mean b)^2)
//
// It is invariant to gain and offset (a -> g a + o, g > 0). A patch whose standard
// deviation is below `min_std` is "constant": its NCC with anything is 0 (never NaN).
// For many pairs, normalize each patch once (normalize_patch) and take dot products
// (ncc_normalized): that is what the measure does.
#pragma once
#include <algorithm>
#include <cmath>

namespace tetmvs::photo {

// Writes (x - mean) / ||x - mean|| to out (out may alias x). Returns false, and writes
// zeros, when the patch is constant (standard deviation < min_std).
inline bool normalize_patch(const float* x, int n, float min_std, float* out) {
  float mean = 0.f;
  for (int i = 0; i < n; ++i) mean += x[i];
  mean /= static_cast<float>(n);
  float ss = 0.f;
  for (int i = 0; i < n; ++i) {
    const float c = x[i] - mean;
    out[i] = c;
    ss += c * c;
  }
  // std = sqrt(ss / n) < min_std  <=>  ss < n min_std^2 (and ss == 0 always counts)
  if (!(ss > static_cast<float>(n) * min_std * min_std) || ss <= 0.f) {
    std::fill(out, out + n, 0.f);
    return false;
  }
  const float inv = 1.f / std::sqrt(ss);
  for (int i = 0; i < n; ++i) out[i] *= inv;
  return true;
}

// NCC of two normalized patches (outputs of normalize_patch): their dot product,
// clamped to [-1, 1] against rounding. 0 when either patch was constant.
inline float ncc_normalized(const float* a, const float* b, int n) {
  float s = 0.f;
  for (int i = 0; i < n; ++i) s += a[i] * b[i];
  return std::clamp(s, -1.f, 1.f);
}

// NCC of two raw patches of n samples (n <= 1024). Convenience for tests and one-off uses.
float ncc(const float* a, const float* b, int n, float min_std = 1e-3f);

}  // namespace tetmvs::photo
