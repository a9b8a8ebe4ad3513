// The options structs bound to params/defaults.json (common/param_binding.h) against the
// file: every binding names a documented parameter of the field's type, every field's default
// is the documented value, no parameter is bound twice, every parameter is bound or read
// directly by the files listed here, and every struct's check() enforces the documented
// ranges, also on a struct built in code.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/cut/graph_cut.h"
#include "common/deform/options.h"
#include "common/error.h"
#include "common/fileio.h"
#include "common/ingest/dataset.h"
#include "common/label/labels.h"
#include "common/param_binding.h"
#include "common/params.h"
#include "common/photo/options.h"
#include "common/photoconsist/occlusion.h"
#include "common/photoconsist/options.h"
#include "common/q_silhouettes.h"
#include "common/silfix/silfix.h"
#include "common/synth/scene.h"

using namespace tetmvs;

namespace param_binding_test {
using json = nlohmann::json;

// Parameters that no struct binds: each is read where it is used (Params::d, i, b, s), by
// these files. A parameter read this way has no default or range outside defaults.json.
const std::map<std::string, std::vector<std::string>> kReadDirectly = {
    {"cut.min_region_fraction", {"stages/cut/main.cpp"}},
    {"eval.threshold", {"common/eval/run.cpp"}},
    {"eval.accuracy_fraction", {"common/eval/run.cpp"}},
    {"eval.sample_spacing_px", {"common/eval/run.cpp"}},
    {"eval.min_views", {"common/eval/run.cpp"}},
    {"eval.visibility_tolerance_px", {"common/eval/run.cpp"}},
    {"eval.png_views", {"common/eval/run.cpp"}},
    {"eval.png_max_error_px", {"common/eval/run.cpp"}},
    {"eval.seed", {"common/eval/run.cpp"}},
    {"eval.roughness_radius_px", {"common/eval/run.cpp", "stages/report/main.cpp"}},
    {"ingest.auto_silhouettes", {"common/ingest/dataset.cpp"}},
    {"ingest.hull_resolution", {"common/ingest/dataset.cpp"}},
    {"ingest.box_padding", {"common/ingest/dataset.cpp", "common/ingest/colmap.cpp"}},
    {"ingest.box", {"common/ingest/dataset.cpp", "common/ingest/colmap.cpp"}},
    {"ingest.roi", {"common/ingest/colmap.cpp"}},
    {"ingest.points_percentile", {"common/ingest/colmap.cpp"}},
    {"ingest.points_min_track", {"common/ingest/colmap.cpp"}},
    {"mesh.cells", {"stages/bcc-init/main.cpp"}},
    {"refine.target_pixels", {"stages/bcc-init/main.cpp", "stages/refine/main.cpp"}},
    {"resource.memory_gb", {"common/budget.cpp"}},
    {"photo.one_sided_deg", {"common/scene.cpp"}},
};

// Parameters bound by two structs, one per stage that uses them.
const std::map<std::string, std::set<std::string>> kBoundTwice = {
    // photoconsist skips the lattice points of the hull core, label labels its cells interior
    {"label.hull_core_px", {"photoconsist::Options", "label::Options"}},
};

struct Binding {
  std::string owner;  // the struct
  std::string key;
  std::string type;   // the field's type as defaults.json names it
  json value;         // the field's default
};

template <class T>
const char* type_name() {
  if constexpr (std::is_same_v<T, int> || std::is_same_v<T, std::uint64_t>) return "int";
  else if constexpr (std::is_same_v<T, double>) return "double";
  else if constexpr (std::is_same_v<T, bool>) return "bool";
  else return "string";
}

template <class S>
void add_bindings(const char* owner, std::vector<Binding>& out) {
  const auto s = std::make_unique<const S>();  // on the heap: GCC's -Wmaybe-uninitialized misreads a local here
  for (const auto& f : S::params())
    std::visit([&](auto m) { out.push_back({owner, f.key, type_name<std::remove_cvref_t<decltype(*s.*m)>>(), json(*s.*m)}); },
               f.field);
}

// Every bound struct: a new one is added here (its parameters are otherwise reported as
// neither bound nor read directly).
std::vector<Binding> all_bindings() {
  std::vector<Binding> b;
  add_bindings<synth::SynthConfig>("synth::SynthConfig", b);
  add_bindings<SilhouetteOptions>("SilhouetteOptions", b);
  add_bindings<photo::Options>("photo::Options", b);
  add_bindings<photoconsist::Options>("photoconsist::Options", b);
  add_bindings<photoconsist::PointMeasure>("photoconsist::PointMeasure", b);
  add_bindings<photoconsist::CrossingRule>("photoconsist::CrossingRule", b);
  add_bindings<photoconsist::OcclusionOptions>("photoconsist::OcclusionOptions", b);
  add_bindings<QSilhouetteOptions>("QSilhouetteOptions", b);
  add_bindings<label::Options>("label::Options", b);
  add_bindings<cut::CutOptions>("cut::CutOptions", b);
  add_bindings<silfix::Options>("silfix::Options", b);
  add_bindings<deform::Options>("deform::Options", b);
  return b;
}

const json& documented() {
  static const Params p = Params::defaults();
  return p.table();
}

std::string message_of_check(const auto& s) {
  try {
    s.check();
  } catch (const Error& e) {
    return e.what();
  }
  return "accepted";
}

// For every numeric field: just below its documented minimum and just above its maximum,
// check() of a struct that holds S at `part` throws an error naming the key; so does a
// string that is not one of the documented choices.
template <class Whole, class S>
void expect_ranges_checked(const Whole& whole, S Whole::*part) {
  static_assert(requires(const Whole& w) { w.check(); }, "a bound struct needs a check()");
  EXPECT_EQ(message_of_check(whole), "accepted");
  for (const auto& f : S::params()) {
    const json& d = documented().at(f.key);
    std::visit(
        [&](auto m) {
          using T = std::remove_cvref_t<decltype(whole.*part.*m)>;
          std::vector<T> bad;
          if constexpr (std::is_same_v<T, std::string>) {
            if (d.contains("choices")) bad.push_back("not one of the choices");
          } else if constexpr (!std::is_same_v<T, bool>) {
            if constexpr (std::is_signed_v<T>) bad.push_back(static_cast<T>(d.at("min").get<double>() - 1));
            bad.push_back(static_cast<T>(d.at("max").get<double>() + 1));
          }
          for (const T& v : bad) {
            Whole w = whole;
            w.*part.*m = v;
            EXPECT_NE(message_of_check(w).find(f.key), std::string::npos)
                << f.key << ": check() of a struct holding it does not name it, value " << json(v).dump();
          }
        },
        f.field);
  }
}

template <class S>
void expect_ranges_checked(const S& s = S{}) {
  struct Holder {
    S s;
    void check() const { s.check(); }
  };
  expect_ranges_checked(Holder{s}, &Holder::s);
}

}  // namespace param_binding_test

using namespace param_binding_test;

TEST(ParamBinding, KeysAreDocumentedWithTheFieldsType) {
  for (const auto& b : all_bindings()) {
    ASSERT_TRUE(documented().contains(b.key)) << b.owner << " binds " << b.key << ", which defaults.json lacks";
    EXPECT_EQ(documented()[b.key]["type"], b.type) << b.owner << " binds " << b.key << " to a field of another type";
  }
}

TEST(ParamBinding, FieldDefaultsAreTheDocumentedValues) {
  for (const auto& b : all_bindings()) {
    if (!documented().contains(b.key)) continue;  // reported above
    EXPECT_EQ(b.value, documented()[b.key]["value"])
        << b.owner << ": the default of the field holding " << b.key << " is " << b.value.dump()
        << ", defaults.json says " << documented()[b.key]["value"].dump();
  }
}

TEST(ParamBinding, NoParameterIsBoundTwice) {
  std::map<std::string, std::set<std::string>> owners;
  std::map<std::string, int> in_struct;
  for (const auto& b : all_bindings()) {
    owners[b.key].insert(b.owner);
    EXPECT_EQ(++in_struct[b.owner + " " + b.key], 1) << b.owner << " binds " << b.key << " twice";
  }
  for (const auto& [key, o] : owners)
    if (o.size() > 1) {
      const auto it = kBoundTwice.find(key);
      EXPECT_TRUE(it != kBoundTwice.end() && it->second == o) << key << " is bound by several structs";
    }
  for (const auto& [key, o] : kBoundTwice) EXPECT_EQ(owners[key], o) << key << " is listed as bound twice";
}

TEST(ParamBinding, NoFieldHoldsTwoParameters) {
  const auto distinct = [](const auto& table) {
    for (std::size_t i = 0; i < table.size(); ++i)
      for (std::size_t j = i + 1; j < table.size(); ++j)
        EXPECT_FALSE(table[i].field == table[j].field) << table[i].key << " and " << table[j].key << " share a field";
  };
  distinct(synth::SynthConfig::params());
  distinct(SilhouetteOptions::params());
  distinct(photo::Options::params());
  distinct(photoconsist::Options::params());
  distinct(photoconsist::PointMeasure::params());
  distinct(photoconsist::CrossingRule::params());
  distinct(photoconsist::OcclusionOptions::params());
  distinct(QSilhouetteOptions::params());
  distinct(label::Options::params());
  distinct(cut::CutOptions::params());
  distinct(silfix::Options::params());
  distinct(deform::Options::params());
}

TEST(ParamBinding, EveryParameterIsBoundOrReadDirectly) {
  std::set<std::string> bound;
  for (const auto& b : all_bindings()) bound.insert(b.key);
  for (const auto& [key, decl] : documented().items()) {
    const bool direct = kReadDirectly.count(key) > 0;
    EXPECT_TRUE(bound.count(key) || direct) << key << " is neither bound to a field nor listed as read directly";
    EXPECT_FALSE(bound.count(key) && direct) << key << " is bound to a field and listed as read directly";
  }
  // The list names files that read the key.
  for (const auto& [key, files] : kReadDirectly) {
    EXPECT_TRUE(documented().contains(key)) << key << " is listed as read directly but defaults.json lacks it";
    for (const auto& f : files)
      EXPECT_NE(read_file(std::filesystem::path(TETMVS_SOURCE_DIR) / f).find("\"" + key + "\""), std::string::npos)
          << f << " does not read " << key;
  }
}

TEST(ParamBinding, NumbersHaveARange) {
  for (const auto& [key, decl] : documented().items()) {
    if (decl["type"] == "int" || decl["type"] == "double") {
      EXPECT_TRUE(decl.contains("min") && decl.contains("max")) << key << " lacks a min or a max";
    }
  }
}

TEST(ParamBinding, ChecksEnforceTheDocumentedRanges) {
  expect_ranges_checked<synth::SynthConfig>();
  expect_ranges_checked<SilhouetteOptions>();
  expect_ranges_checked<photo::Options>();
  expect_ranges_checked<photoconsist::PointMeasure>();
  expect_ranges_checked<photoconsist::CrossingRule>();
  expect_ranges_checked<photoconsist::OcclusionOptions>();
  expect_ranges_checked<QSilhouetteOptions>();
  expect_ranges_checked<cut::CutOptions>();
  expect_ranges_checked<silfix::Options>();
  expect_ranges_checked<deform::Options>();
  // the structs that hold others check those too
  const photoconsist::Options pc;
  expect_ranges_checked(pc, &photoconsist::Options::face);
  expect_ranges_checked(pc, &photoconsist::Options::q_sil);
  expect_ranges_checked(pc, &photoconsist::Options::rule);
  expect_ranges_checked(pc, &photoconsist::Options::occl);
  expect_ranges_checked<photoconsist::Options>();
  expect_ranges_checked(label::Options{}, &label::Options::q_sil);
  expect_ranges_checked<label::Options>();
}

TEST(ParamBinding, MessagesNameTheKeyTheValueAndTheRange) {
  deform::Options o;
  o.smooth_bilaplacian = 0.6;
  const std::string m = message_of_check(o);
  EXPECT_NE(m.find("deform.smooth_bilaplacian = 0.6 must lie in [0.0, 0.49]"), std::string::npos) << m;
  photoconsist::CrossingRule r;
  r.combine = "mean";
  const std::string c = message_of_check(r);
  EXPECT_NE(c.find("photo.cross_rule = 'mean' must be one of [\"min\",\"max\"]"), std::string::npos) << c;
}

// from_params reads the parts that a struct holds: one parameter of each part changed.
TEST(ParamBinding, FromParamsReadsEveryPart) {
  Params p = Params::defaults();
  for (const char* kv : {"photo.mu=9", "photo.point_k=12", "photo.point_patch=line", "photo.line_mu=15",
                         "photo.q_hull_min_points=7", "photo.cross_rule=max", "photo.occlusion=true",
                         "photo.lattice_px=1.5", "label.hull_core_px=2", "label.seen_free_views=4"})
    p.set(kv);
  const auto pc = photoconsist::Options::from_params(p);
  EXPECT_EQ(pc.face.mu, 9);
  EXPECT_EQ(pc.line.k, 12);
  EXPECT_EQ(pc.line.mu, 15);
  EXPECT_FALSE(pc.line.point_grid);
  EXPECT_EQ(pc.q_sil.min_points, 7);
  EXPECT_EQ(pc.rule.combine, "max");
  EXPECT_TRUE(pc.occl.enabled);
  EXPECT_EQ(pc.lattice_px, 1.5);
  EXPECT_EQ(pc.hull_core_px, 2);
  const auto lo = label::Options::from_params(p);
  EXPECT_EQ(lo.q_sil.min_points, 7);
  EXPECT_EQ(lo.hull_core_px, 2);
  EXPECT_EQ(lo.seen_free_views, 4);
}
