// libFuzzer target: the strict Middlebury par reader. Any input must either parse or
// throw tetmvs::Error; nothing else (no crash, no other exception, no sanitizer report).
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <string>

#include "common/error.h"
#include "common/par_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/tetmvs_fuzz_par_" + std::to_string(::getpid()) + "_par.txt";
  {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    const auto cams = tetmvs::read_par(path);
    for (const auto& c : cams)
      if (!c.K.allFinite() || !c.R.allFinite() || !c.t.allFinite()) __builtin_trap();
  } catch (const tetmvs::Error&) {
  }
  return 0;
}
