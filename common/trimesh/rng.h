// Small deterministic random numbers keyed by (seed, index...), so that results do not
// depend on the thread count or loop order.
#pragma once
#include <cmath>
#include <cstdint>

namespace tetmvs {

inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}
inline std::uint64_t hash_combine(std::uint64_t a, std::uint64_t b) { return splitmix64(a ^ splitmix64(b)); }

// Counter-based generator: a stream per key.
class Rng {
 public:
  explicit Rng(std::uint64_t key) : s_(splitmix64(key)) {}
  Rng(std::uint64_t seed, std::uint64_t index) : s_(hash_combine(seed, index)) {}
  std::uint64_t next() { return splitmix64(s_++); }
  // Uniform in [0, 1).
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  // Standard normal (Box-Muller; one value per call).
  double normal() {
    double u1 = uniform();
    while (u1 <= 0) u1 = uniform();
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }

 private:
  std::uint64_t s_;
};

}  // namespace tetmvs
