#include "common/synth/texture.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "common/error.h"
#include "common/trimesh/rng.h"

namespace tetmvs::synth {

namespace {
inline std::uint32_t hash3(std::int32_t x, std::int32_t y, std::int32_t z, std::uint32_t s) {
  std::uint32_t h = s ^ 0x9E3779B9u;
  h ^= static_cast<std::uint32_t>(x) * 0x85EBCA6Bu;
  h = (h << 13) | (h >> 19);
  h ^= static_cast<std::uint32_t>(y) * 0xC2B2AE35u;
  h = (h << 13) | (h >> 19);
  h ^= static_cast<std::uint32_t>(z) * 0x27D4EB2Fu;
  h ^= h >> 16;
  h *= 0x7FEB352Du;
  h ^= h >> 15;
  h *= 0x846CA68Bu;
  h ^= h >> 16;
  return h;
}
inline float corner(std::int32_t x, std::int32_t y, std::int32_t z, std::uint32_t s) {
  return static_cast<float>(hash3(x, y, z, s) >> 8) * (1.0f / 16777216.0f);
}
inline double fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }
}  // namespace

SolidTexture::SolidTexture(const TextureOptions& o) : o_(o) {
  require(o.strength >= 0 && o.strength <= 1, "texture strength must be in [0, 1], got ", o.strength);
  require(o.min_scale > 0 && o.max_scale >= o.min_scale, "texture scales must satisfy 0 < min <= max, got ",
          o.min_scale, " and ", o.max_scale);
  octaves_ = 1 + static_cast<int>(std::floor(std::log2(o.max_scale / o.min_scale) + 1e-9));
  seed32_ = static_cast<std::uint32_t>(splitmix64(o.seed));
  for (int k = 0; k <= octaves_; ++k) {  // one more for the tint
    Rng r(o.seed, 1000 + k);
    Eigen::Quaterniond q(r.normal(), r.normal(), r.normal(), r.normal());
    q.normalize();
    rot_.push_back(q.toRotationMatrix());
  }
}

float SolidTexture::octave_noise(const Eigen::Vector3d& X, double wavelength, std::uint32_t salt) const {
  const double x = X.x() / wavelength, y = X.y() / wavelength, z = X.z() / wavelength;
  const double fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  const auto ix = static_cast<std::int32_t>(fx), iy = static_cast<std::int32_t>(fy), iz = static_cast<std::int32_t>(fz);
  const double tx = fade(x - fx), ty = fade(y - fy), tz = fade(z - fz);
  const std::uint32_t s = seed32_ ^ (salt * 0x632BE5ABu);
  auto lerp = [](double a, double b, double t) { return a + (b - a) * t; };
  const double c00 = lerp(corner(ix, iy, iz, s), corner(ix + 1, iy, iz, s), tx);
  const double c10 = lerp(corner(ix, iy + 1, iz, s), corner(ix + 1, iy + 1, iz, s), tx);
  const double c01 = lerp(corner(ix, iy, iz + 1, s), corner(ix + 1, iy, iz + 1, s), tx);
  const double c11 = lerp(corner(ix, iy + 1, iz + 1, s), corner(ix + 1, iy + 1, iz + 1, s), tx);
  return static_cast<float>(lerp(lerp(c00, c10, ty), lerp(c01, c11, ty), tz));
}

float SolidTexture::pattern(const Eigen::Vector3d& X) const {
  double sum = 0;
  double w = o_.max_scale;
  for (int k = 0; k < octaves_; ++k, w *= 0.5) sum += octave_noise(rot_[k] * X, w, 1 + k);
  // Mean 0.5; the average of k octaves has a spread of about 0.1 / sqrt(k): stretch it.
  const double v = 0.5 + (sum / octaves_ - 0.5) * 1.5 * std::sqrt(static_cast<double>(octaves_));
  return static_cast<float>(std::clamp(v, 0.0, 1.0));
}

Eigen::Vector3f SolidTexture::albedo(const Eigen::Vector3d& X) const {
  const double s = o_.strength;
  const double p = s > 0 ? pattern(X) : 0.6;
  const double a = 0.2 + 0.75 * ((1 - s) * 0.6 + s * p);
  // Slow tint between a warm and a cool colour (wavelength 4 x max_scale).
  const double t = s > 0 ? octave_noise(rot_[octaves_] * X, 4 * o_.max_scale, 97) : 0.0;
  const Eigen::Vector3d warm(1.0, 0.86, 0.72), cool(0.78, 0.9, 1.0), grey(0.95, 0.95, 0.95);
  const Eigen::Vector3d tint = (1 - s) * grey + s * ((1 - t) * warm + t * cool);
  return (a * tint).cast<float>();
}

}  // namespace tetmvs::synth
