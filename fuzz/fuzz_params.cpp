// libFuzzer target: parameter overrides (JSON files and --set key=value). Any input
// must be accepted or rejected with tetmvs::Error, and what was accepted must read back
// with its declared type. scripts/fuzz.sh passes fuzz/params.dict (keys, awkward numbers).
#include <cstdint>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/params.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string s(reinterpret_cast<const char*>(data), size);
  static const tetmvs::Params defaults = tetmvs::Params::defaults();  // parsed once
  tetmvs::Params p = defaults;
  try {
    p.set(s);
  } catch (const tetmvs::Error&) {
  }
  // structure-aware: the first byte picks a declared key, the rest is its value
  if (size > 0) {
    static const std::vector<std::string> keys = defaults.keys_for("");
    try {
      p.set(keys[data[0] % keys.size()] + "=" + s.substr(1));
    } catch (const tetmvs::Error&) {
    }
  }
  try {
    const auto j = nlohmann::json::parse(s, nullptr, /*allow_exceptions=*/false);
    if (!j.is_discarded()) p.merge(j, "fuzz.json");
  } catch (const tetmvs::Error&) {
  }
  // whatever was accepted must read back with its declared type
  for (const auto& k : p.keys_for("")) {
    const std::string t = p.table()[k]["type"];
    try {
      if (t == "double") (void)p.d(k);
      else if (t == "int") (void)p.i(k);
      else if (t == "bool") (void)p.b(k);
      else (void)p.s(k);
    } catch (const tetmvs::Error&) {
      __builtin_trap();
    }
  }
  return 0;
}
