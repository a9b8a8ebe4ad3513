// Open-addressing hash map from an undirected edge (two vertex ids) to its midpoint
// vertex. Lookups are read-only and thread-safe; inserts are single-threaded.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

namespace tetmvs::tet {

class EdgeMap {
 public:
  explicit EdgeMap(std::size_t expected = 1024) { rehash(expected * 2 + 16); }

  static std::uint64_t key(std::int32_t a, std::int32_t b) {
    if (a > b) std::swap(a, b);
    return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
  }
  // Midpoint of edge (a, b), -1 when the edge is not split.
  std::int32_t find(std::int32_t a, std::int32_t b) const {
    const std::uint64_t k = key(a, b);
    std::size_t i = slot(k);
    while (true) {
      const std::uint64_t s = keys_[i];
      if (s == k) return vals_[i];
      if (s == kEmpty) return -1;
      i = (i + 1) & mask_;
    }
  }
  bool has(std::int32_t a, std::int32_t b) const { return find(a, b) >= 0; }
  // Inserts (a,b) -> v unless present; returns the stored midpoint.
  std::int32_t insert(std::int32_t a, std::int32_t b, std::int32_t v) {
    if ((size_ + 1) * 2 > keys_.size()) rehash(keys_.size() * 2);
    const std::uint64_t k = key(a, b);
    std::size_t i = slot(k);
    while (true) {
      if (keys_[i] == k) return vals_[i];
      if (keys_[i] == kEmpty) {
        keys_[i] = k;
        vals_[i] = v;
        ++size_;
        return v;
      }
      i = (i + 1) & mask_;
    }
  }
  std::size_t size() const { return size_; }
  void reserve(std::size_t n) {
    if (n * 2 > keys_.size()) rehash(n * 2);
  }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
  std::size_t slot(std::uint64_t k) const {
    k ^= k >> 29;
    k *= 0xbf58476d1ce4e5b9ULL;
    k ^= k >> 32;
    return static_cast<std::size_t>(k) & mask_;
  }
  void rehash(std::size_t want) {
    std::size_t cap = 16;
    while (cap < want) cap <<= 1;
    std::vector<std::uint64_t> ok = std::move(keys_);
    std::vector<std::int32_t> ov = std::move(vals_);
    keys_.assign(cap, kEmpty);
    vals_.assign(cap, -1);
    mask_ = cap - 1;
    size_ = 0;
    for (std::size_t i = 0; i < ok.size(); ++i)
      if (ok[i] != kEmpty) {
        std::size_t j = slot(ok[i]);
        while (keys_[j] != kEmpty) j = (j + 1) & mask_;
        keys_[j] = ok[i];
        vals_[j] = ov[i];
        ++size_;
      }
  }
  std::vector<std::uint64_t> keys_;
  std::vector<std::int32_t> vals_;
  std::size_t mask_ = 0, size_ = 0;
};

}  // namespace tetmvs::tet
