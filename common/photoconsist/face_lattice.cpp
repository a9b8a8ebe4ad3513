#include "common/photoconsist/face_lattice.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace tetmvs::photoconsist {

int reusable_divisions(int need) {
  require(need >= 1 && need < (1 << 24), "photoconsist: a face needs ", need, " lattice divisions");
  int best = 1;
  while (best < need) best *= 2;  // 2^e
  for (int t = 3; t < best; t *= 2)
    if (t >= need) return t;  // 3 * 2^e, smaller than the power of two
  return best;
}

std::uint16_t encode_point(const photo::PointResult& r, const photo::Options& opts) {
  if (!r.valid()) return kCodeNoScore;
  const double s = std::clamp(static_cast<double>(r.score), -1.0, 1.0);
  auto q = static_cast<std::uint16_t>(2 + std::lround((s + 1.0) / 2.0 * 32765.0));
  if (r.consistent(opts)) q |= kCodeConsistent;
  return q;
}

float code_score(std::uint16_t c) {
  const int q = c & 0x7fff;
  if (q < 2) return photo::kNoScore;
  return static_cast<float>((q - 2) / 32765.0 * 2.0 - 1.0);
}

bool map_sub_lattice(const FaceLat& P, int n, const FaceLat& C, int* child_n,
                     std::vector<std::int64_t>& index) {
  if (n < 1) return false;
  // Doubled parent coordinates (2I, 2J) of the six candidate points.
  const std::int64_t N = n;
  const std::int64_t cand[6][2] = {{0, 0}, {2 * N, 0}, {0, 2 * N}, {N, 0}, {N, N}, {0, N}};
  const int ends[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {2, 0}};
  std::int64_t D[3][2];
  bool any_mid = false;
  for (int v = 0; v < 3; ++v) {
    int found = -1;
    for (int c = 0; c < 6 && found < 0; ++c) {
      bool eq = true;
      for (int k = 0; k < 3; ++k) {
        const std::int64_t two_v = 2 * static_cast<std::int64_t>(C[3 * v + k]);
        const std::int64_t s = static_cast<std::int64_t>(P[3 * ends[c][0] + k]) + P[3 * ends[c][1] + k];
        if (two_v != s) eq = false;
      }
      if (eq) found = c;
    }
    if (found < 0) return false;
    D[v][0] = cand[found][0];
    D[v][1] = cand[found][1];
    any_mid = any_mid || found >= 3;
  }
  if (any_mid && n % 2 != 0) return false;
  const std::int64_t m = any_mid ? N / 2 : N;
  const std::int64_t e1[2] = {D[1][0] - D[0][0], D[1][1] - D[0][1]};
  const std::int64_t e2[2] = {D[2][0] - D[0][0], D[2][1] - D[0][1]};
  const std::int64_t det = e1[0] * e2[1] - e1[1] * e2[0];
  // Doubled coordinates: the whole face has |det| = 4 n^2, a quarter n^2.
  if (std::abs(det) != (any_mid ? N * N : 4 * N * N)) return false;
  for (int k = 0; k < 2; ++k)
    if (e1[k] % m != 0 || e2[k] % m != 0) return false;
  const std::int64_t s1[2] = {e1[0] / m, e1[1] / m}, s2[2] = {e2[0] / m, e2[1] / m};
  const int mi = static_cast<int>(m);
  index.resize(static_cast<std::size_t>(lattice_size(mi)));
  std::int64_t p = 0;
  for (int j = 0; j <= mi; ++j)
    for (int i = 0; i + j <= mi; ++i) {
      const std::int64_t I2 = D[0][0] + i * s1[0] + j * s2[0], J2 = D[0][1] + i * s1[1] + j * s2[1];
      if (I2 % 2 != 0 || J2 % 2 != 0 || I2 < 0 || J2 < 0 || I2 / 2 + J2 / 2 > N) return false;
      index[p++] = lattice_index(n, static_cast<int>(I2 / 2), static_cast<int>(J2 / 2));
    }
  *child_n = mi;
  return true;
}

}  // namespace tetmvs::photoconsist
