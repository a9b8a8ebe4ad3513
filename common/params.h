// Parameters: one JSON file of documented defaults (params/defaults.json, compiled in),
// per-dataset JSON overrides ({"key": value, ...}), and --set key=value on the command
// line, applied in that order. Unknown keys, wrong types and values out of the
// documented range are errors. Each parameter has a tier: "paper" (the paper's own
// parameters), "extension" (the main setting of an extension of the paper) or "expert"
// (details a user rarely changes; --help lists them only with --help-all).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tetmvs {

class Params {
 public:
  static Params defaults();
  // Applies a JSON object of overrides; `origin` names it in error messages.
  void merge(const nlohmann::json& overrides, const std::string& origin);
  void merge_file(const std::filesystem::path& file);
  // "key=value"; the value is parsed by the key's declared type.
  void set(const std::string& key_eq_value);

  double d(const std::string& key) const;
  int i(const std::string& key) const;
  bool b(const std::string& key) const;
  std::string s(const std::string& key) const;
  bool has(const std::string& key) const;

  // {"key": value} of every parameter whose "stages" list names `stage`
  // (all parameters when stage is empty): stored in the outputs' "params" attribute.
  nlohmann::json values_for(const std::string& stage = "") const;
  // Keys used by a stage, sorted.
  std::vector<std::string> keys_for(const std::string& stage) const;
  // The full documented table (defaults.json with current values).
  const nlohmann::json& table() const { return table_; }
  // Text for a stage's --help: its parameters with default, unit, tier and paper value;
  // the expert tier only when `all` (--help-all).
  std::string help_for(const std::string& stage, bool all = false) const;

 private:
  void set_value(const std::string& key, const nlohmann::json& v, const std::string& origin);
  nlohmann::json table_;  // key -> {value, type, unit, meaning, paper, min, max, stages, make}
};

}  // namespace tetmvs
