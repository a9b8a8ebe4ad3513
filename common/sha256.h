// SHA-256 (FIPS 180-4), for input provenance attributes and dataset checks: OpenSSL's
// libcrypto (which uses the CPU's SHA instructions where there are any).
#pragma once
#include <cstddef>
#include <memory>
#include <string>

namespace tetmvs {

class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;
  void update(const void* data, std::size_t n);
  std::string hex();  // finishes; lowercase hex digest

 private:
  struct Context;
  std::unique_ptr<Context> ctx_;
};

std::string sha256_hex(const std::string& bytes);

}  // namespace tetmvs
