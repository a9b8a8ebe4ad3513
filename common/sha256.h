// SHA-256 (FIPS 180-4), for input provenance attributes and dataset checks.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace tetmvs {

class Sha256 {
 public:
  Sha256();
  void update(const void* data, std::size_t n);
  std::string hex();  // finishes; lowercase hex digest

 private:
  void block(const std::uint8_t* p);
  std::uint32_t h_[8];
  std::uint8_t buf_[64];
  std::size_t buflen_ = 0;
  std::uint64_t total_ = 0;
};

std::string sha256_hex(const std::string& bytes);

}  // namespace tetmvs
