// Options structs bound to params/defaults.json. A struct that holds parameters lists once
// which field holds which parameter, in a static member function params():
//
//   struct Options {
//     int iterations = 16;   // the default: the same as defaults.json's "value"
//     void check() const;    // check_param_ranges(*this), then the rules the table cannot state
//     static constexpr auto params() {
//       return std::to_array<ParamField<Options>>({{"deform.iterations", &Options::iterations}});
//     }
//   };
//
// read_params copies the values of a Params into the fields; check_param_ranges checks the
// fields against the ranges ("min", "max") and "choices" that defaults.json documents, so a
// struct built in code is held to the same ranges as one read from the parameters. The
// unit test ParamBinding (tests/unit/test_param_binding.cpp) checks every table against
// defaults.json: the key exists with the field's type, the field's default is the documented
// value, no key is bound twice, and every parameter is bound or read directly by a stage.
#pragma once
#include <cstdint>
#include <string>
#include <variant>

namespace tetmvs {
class Params;

// A field of S holding the parameter `key`. Parameters of type "int" bind to int or
// std::uint64_t fields, "double" to double, "bool" to bool, "string" to std::string.
template <class S>
struct ParamField {
  const char* key;
  std::variant<int S::*, std::uint64_t S::*, double S::*, bool S::*, std::string S::*> field;
};

namespace param_detail {
void read(const Params& p, const char* key, int& v);
void read(const Params& p, const char* key, std::uint64_t& v);
void read(const Params& p, const char* key, double& v);
void read(const Params& p, const char* key, bool& v);
void read(const Params& p, const char* key, std::string& v);
void check(const char* key, int v);
void check(const char* key, std::uint64_t v);
void check(const char* key, double v);
void check(const char* key, bool v);
void check(const char* key, const std::string& v);
}  // namespace param_detail

// Sets every field S::params() binds to its parameter's value in p.
template <class S>
void read_params(const Params& p, S& s) {
  for (const auto& f : S::params()) std::visit([&](auto m) { param_detail::read(p, f.key, s.*m); }, f.field);
}

// Throws an Error naming the key, the value and the documented range (or choices) when a
// bound field lies outside what params/defaults.json allows; a double must be finite.
template <class S>
void check_param_ranges(const S& s) {
  for (const auto& f : S::params()) std::visit([&](auto m) { param_detail::check(f.key, s.*m); }, f.field);
}

}  // namespace tetmvs
