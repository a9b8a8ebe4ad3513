#include "common/param_binding.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/params.h"

namespace tetmvs::param_detail {
namespace {
using json = nlohmann::json;

// The declaration of `key` in params/defaults.json (parsed once), which must be of `type`.
const json& declared(const char* key, const char* type) {
  static const Params documented = Params::defaults();
  const json& table = documented.table();
  if (!table.contains(key)) fail("internal: parameter '", key, "' is not declared in params/defaults.json");
  const json& d = table.at(key);
  if (d.at("type") != type)
    fail("internal: parameter '", key, "' is a ", d.at("type").get<std::string>(), ", bound to a field of type ", type);
  return d;
}

void check_number(const char* key, const char* type, double v, const std::string& shown) {
  const json& d = declared(key, type);
  const bool below = d.contains("min") && !(v >= d["min"].get<double>());
  const bool above = d.contains("max") && !(v <= d["max"].get<double>());
  if (below || above || !std::isfinite(v))
    fail("parameter ", key, " = ", shown, " must lie in [", d.contains("min") ? d["min"].dump() : "-inf", ", ",
         d.contains("max") ? d["max"].dump() : "inf", "] (", d.at("meaning").get<std::string>(), ")");
}
}  // namespace

void read(const Params& p, const char* key, int& v) { v = p.i(key); }
void read(const Params& p, const char* key, std::uint64_t& v) {
  const int i = p.i(key);
  if (i < 0) fail("parameter ", key, " = ", i, " must be >= 0");
  v = static_cast<std::uint64_t>(i);
}
void read(const Params& p, const char* key, double& v) { v = p.d(key); }
void read(const Params& p, const char* key, bool& v) { v = p.b(key); }
void read(const Params& p, const char* key, std::string& v) { v = p.s(key); }

void check(const char* key, int v) { check_number(key, "int", v, std::to_string(v)); }
void check(const char* key, std::uint64_t v) {
  check_number(key, "int", static_cast<double>(v), std::to_string(v));
}
void check(const char* key, double v) {
  std::ostringstream os;
  os << v;
  check_number(key, "double", v, os.str());
}
void check(const char* key, bool) { declared(key, "bool"); }
void check(const char* key, const std::string& v) {
  const json& d = declared(key, "string");
  if (!d.contains("choices")) return;
  const json& ch = d["choices"];
  if (std::find(ch.begin(), ch.end(), json(v)) == ch.end())
    fail("parameter ", key, " = '", v, "' must be one of ", ch.dump(), " (", d.at("meaning").get<std::string>(), ")");
}

}  // namespace tetmvs::param_detail
