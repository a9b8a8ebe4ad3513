#include "common/params.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string_view>

#include "common/error.h"
#include "common/fileio.h"

namespace tetmvs {

extern const std::string_view kDefaultParamsJson;

namespace {
using json = nlohmann::json;

// Converts v to the declared type of the parameter, or throws.
json coerce(const json& decl, const json& v, const std::string& key, const std::string& origin) {
  const std::string type = decl.at("type");
  const auto bad = [&](const std::string& why) {
    fail(origin, ": parameter ", key, " ", why, " (", decl.value("meaning", ""), ")");
  };
  json out;
  if (type == "double") {
    if (!v.is_number()) bad("must be a number, got " + v.dump());
    const double d = v.get<double>();
    if (!std::isfinite(d)) bad("must be finite");
    out = d;
  } else if (type == "int") {
    // whole numbers within +-2^53 only (checked before any conversion: casting a larger
    // value, e.g. 1e300 or 2^64-1, overflows)
    constexpr double kMaxExact = 9007199254740992.0;
    const double d = v.is_number() ? v.get<double>() : NAN;
    if (!(std::abs(d) <= kMaxExact) || d != std::floor(d)) bad("must be an integer, got " + v.dump());
    out = v.is_number_integer() && !v.is_number_unsigned() ? v.get<long long>() : static_cast<long long>(d);
  } else if (type == "bool") {
    if (!v.is_boolean()) bad("must be true or false, got " + v.dump());
    out = v;
  } else if (type == "string") {
    if (!v.is_string()) bad("must be a string, got " + v.dump());
    out = v;
    if (decl.contains("choices")) {
      const auto& ch = decl["choices"];
      if (std::find(ch.begin(), ch.end(), v) == ch.end()) bad("must be one of " + ch.dump());
    }
  } else {
    fail("params/defaults.json: parameter ", key, " has unknown type ", type);
  }
  if (out.is_number()) {
    const double d = out.get<double>();
    if (decl.contains("min") && d < decl["min"].get<double>())
      bad("= " + out.dump() + " is below its minimum " + decl["min"].dump());
    if (decl.contains("max") && d > decl["max"].get<double>())
      bad("= " + out.dump() + " is above its maximum " + decl["max"].dump());
  }
  return out;
}

std::string trim(std::string s) {
  const auto b = s.find_first_not_of(" \t");
  const auto e = s.find_last_not_of(" \t");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}
}  // namespace

Params Params::defaults() {
  Params p;
  try {
    p.table_ = json::parse(kDefaultParamsJson);
  } catch (const json::exception& e) {
    fail("params/defaults.json: invalid JSON: ", e.what());
  }
  for (auto& [key, decl] : p.table_.items()) {
    for (const char* f : {"value", "type", "meaning", "stages", "tier"})
      if (!decl.contains(f)) fail("params/defaults.json: parameter ", key, " lacks '", f, "'");
    const std::string tier = decl["tier"].is_string() ? decl["tier"].get<std::string>() : "";
    if (tier != "paper" && tier != "extension" && tier != "expert")
      fail("params/defaults.json: parameter ", key, " has tier '", tier, "' (paper, extension or expert)");
    decl["value"] = coerce(decl, decl["value"], key, "params/defaults.json");
  }
  return p;
}

void Params::set_value(const std::string& key, const json& v, const std::string& origin) {
  if (!table_.contains(key)) {
    // suggest keys sharing the suffix, the usual typo
    std::string hint;
    const auto dot = key.rfind('.');
    const std::string leaf = dot == std::string::npos ? key : key.substr(dot + 1);
    for (auto& [k, d] : table_.items())
      if (k.size() >= leaf.size() && k.compare(k.size() - leaf.size(), leaf.size(), leaf) == 0)
        hint = " (did you mean " + k + "?)";
    fail(origin, ": unknown parameter '", key, "'", hint);
  }
  auto& decl = table_[key];
  decl["value"] = coerce(decl, v, key, origin);
}

void Params::merge(const json& overrides, const std::string& origin) {
  if (!overrides.is_object()) fail(origin, ": parameter overrides must be a JSON object {\"key\": value}");
  for (auto& [k, v] : overrides.items()) {
    if (!k.empty() && k[0] == '_') continue;  // comments: "_comment": "..."
    set_value(k, v, origin);
  }
}

void Params::merge_file(const std::filesystem::path& file) {
  const std::string text = read_file(file);
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    fail(file.string(), ": invalid JSON: ", e.what());
  }
  merge(j, file.string());
}

void Params::set(const std::string& kv) {
  const auto eq = kv.find('=');
  if (eq == std::string::npos) fail("--set ", kv, ": expected key=value");
  const std::string key = trim(kv.substr(0, eq)), val = trim(kv.substr(eq + 1));
  if (!table_.contains(key)) set_value(key, json(), "--set");  // throws unknown-key error
  const std::string type = table_[key]["type"];
  json v;
  if (type == "string") {
    v = val;
  } else {
    try {
      v = json::parse(val);
    } catch (const json::exception&) {
      fail("--set ", key, "=", val, ": value is not a valid ", type);
    }
  }
  set_value(key, v, "--set " + key);
}

bool Params::has(const std::string& key) const { return table_.contains(key); }

namespace {
const json& value_of(const json& table, const std::string& key, const char* want) {
  if (!table.contains(key)) fail("internal: parameter '", key, "' is not declared in params/defaults.json");
  const json& d = table.at(key);
  if (d.at("type") != want)
    fail("internal: parameter '", key, "' is a ", d.at("type").get<std::string>(), ", read as ", want);
  return d.at("value");
}
}  // namespace

double Params::d(const std::string& key) const { return value_of(table_, key, "double").get<double>(); }
int Params::i(const std::string& key) const {
  const long long v = value_of(table_, key, "int").get<long long>();
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
    fail("parameter ", key, " = ", v, " does not fit a 32-bit integer (its range in params/defaults.json is too wide)");
  return static_cast<int>(v);
}
bool Params::b(const std::string& key) const { return value_of(table_, key, "bool").get<bool>(); }
std::string Params::s(const std::string& key) const {
  return value_of(table_, key, "string").get<std::string>();
}

std::vector<std::string> Params::keys_for(const std::string& stage) const {
  std::vector<std::string> keys;
  for (auto& [k, d] : table_.items()) {
    const auto& st = d.at("stages");
    if (stage.empty() || std::find(st.begin(), st.end(), stage) != st.end()) keys.push_back(k);
  }
  std::sort(keys.begin(), keys.end());
  return keys;
}

json Params::values_for(const std::string& stage) const {
  json out = json::object();
  for (const auto& k : keys_for(stage)) out[k] = table_.at(k).at("value");
  return out;
}

std::string Params::help_for(const std::string& stage, bool all) const {
  std::ostringstream os;
  const auto keys = keys_for(stage);
  if (keys.empty()) return "";
  int hidden = 0;
  for (const auto& k : keys) hidden += !all && table_.at(k).at("tier") == "expert";
  os << "Parameters (--set key=value; make variable in brackets)"
     << (all ? " of every tier" : hidden > 0 ? ": the paper's and the extensions'; --help-all also lists " +
                                                   std::to_string(hidden) + " expert ones"
                                             : "")
     << ":\n";
  for (const auto& k : keys) {
    const auto& d = table_.at(k);
    if (!all && d.at("tier") == "expert") continue;
    os << "  " << k << " = " << d.at("value").dump();
    if (d.contains("unit") && !d["unit"].get<std::string>().empty()) os << " [" << d["unit"].get<std::string>() << "]";
    if (d.contains("make")) os << "  (" << d["make"].get<std::string>() << ")";
    os << "  {" << d.at("tier").get<std::string>() << "}";
    os << "\n      " << d.at("meaning").get<std::string>();
    if (d.contains("paper")) os << " Paper: " << d["paper"].get<std::string>() << ".";
    os << "\n";
  }
  return os.str();
}

}  // namespace tetmvs
