// Solid (3-D) texture for synthetic scenes: the albedo is a function of the world
// point, so every view sees the same surface pattern. Multi-octave value noise with
// wavelengths from min_scale to max_scale (world units), tinted by a slow colour noise.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace tetmvs::synth {

struct TextureOptions {
  double strength = 1.0;     // 0 = uniform albedo (textureless), 1 = full contrast
  double min_scale = 5e-4;   // finest noise wavelength (world units)
  double max_scale = 8e-3;   // coarsest noise wavelength (world units)
  std::uint64_t seed = 1;
};

class SolidTexture {
 public:
  explicit SolidTexture(const TextureOptions& o);
  // Pattern value in [0, 1] at X (before strength and tint).
  float pattern(const Eigen::Vector3d& X) const;
  // RGB albedo in about [0.2, 0.95].
  Eigen::Vector3f albedo(const Eigen::Vector3d& X) const;
  const TextureOptions& options() const { return o_; }

 private:
  float octave_noise(const Eigen::Vector3d& X, double wavelength, std::uint32_t salt) const;
  TextureOptions o_;
  std::vector<Eigen::Matrix3d> rot_;  // a random rotation per octave (no axis-aligned blocks)
  int octaves_ = 1;
  std::uint32_t seed32_ = 0;
};

}  // namespace tetmvs::synth
