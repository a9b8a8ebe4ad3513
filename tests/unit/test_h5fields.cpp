// The table-driven output writer (common/h5fields.h): what each kind of row writes, in which
// dtype and shape, optional rows, groups with their own tables, and the summary line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/h5fields.h"
#include "common/h5io.h"

namespace fs = std::filesystem;
using namespace tetmvs;

namespace {

struct FieldsRow {
  std::int32_t id = 0;
  float weight = 0;
};

struct FieldsPart {
  std::vector<std::int64_t> offsets;
  std::string signature;
  double scale = 0;
};

struct FieldsResult {
  std::vector<std::int8_t> label;
  std::vector<double> position;  // n x 3
  std::vector<FieldsRow> rows;
  std::int64_t interior = 0;
  double low = 0;
  bool closed = false;
  int level = 0;
  std::string note;
  std::vector<double> box;
  std::optional<double> measured;
  std::optional<std::vector<float>> extra;
  std::optional<FieldsPart> eval;
  FieldsPart cache;
  bool occluded = false;
};

h5::Fields<FieldsPart> part_table() {
  return h5::Fields<FieldsPart>()
      .dataset("offsets", &FieldsPart::offsets)
      .attr("", "signature", &FieldsPart::signature)
      .attr("", "scale", &FieldsPart::scale).show("scale", 2);
}

h5::Fields<FieldsResult> result_table() {
  using R = FieldsResult;
  return h5::Fields<R>()
      .attr("/", "level", &R::level).show()
      .dataset("/cells/label", &R::label)
      .dataset("/points/position", &R::position, 3)
      .dataset("/rows/id", [](const R& r) { return h5::column(r.rows, &FieldsRow::id); })
      .dataset("/rows/weight", [](const R& r) { return h5::column(r.rows, &FieldsRow::weight); })
      .count("rows", [](const R& r) { return r.rows.size(); })
      .attr("/", "interior", &R::interior).show("inside")
      .attr("/", "low", &R::low).show()
      .text("; shape:")
      .attr("/", "closed", &R::closed).show()
      .attr("/", "note", &R::note)
      .attr("/", "box", &R::box)
      .attr("/points", "measured", &R::measured).show()
      .dataset("/cells/extra", &R::extra)
      .attr("/cells", "occluders", [](const R& r) { return r.interior * 2; }).show("occluders").show_when(
          [](const R& r) { return r.occluded; })
      .count("ratio", [](const R& r) { return std::to_string(r.interior) + "/" + std::to_string(r.label.size()); })
      .when([](const R& r) { return !r.label.empty(); })
      .group("/cache", &R::cache, part_table())
      .group("/eval", &R::eval, part_table());
}

FieldsResult sample_result() {
  FieldsResult r;
  r.label = {1, -1, 0, 1};
  r.position = {0, 1, 2, 3, 4, 5};
  r.rows = {{7, 0.5f}, {8, 1.5f}, {9, 2.5f}};
  r.interior = 2;
  r.low = 0.25;
  r.closed = true;
  r.level = 3;
  r.note = "all of it";
  r.box = {-1, -2, -3, 1, 2, 3};
  r.cache = {{0, 4, 9}, "sig-1", 1.23456};
  return r;
}

fs::path fields_file(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("tetmvs_h5fields_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d / (name + ".h5");
}

}  // namespace

TEST(H5Fields, WritesEachRowWithTheDtypeAndShapeOfItsGetter) {
  const fs::path p = fields_file("rows");
  const FieldsResult r = sample_result();
  {
    auto f = h5::File::create(p);
    result_table().write(f, r);
    f.commit();
  }
  const auto f = h5::File::open(p);
  // datasets: the element type of the vector, shape (n,) or (n / cols, cols)
  EXPECT_EQ(f.read<std::int8_t>("/cells/label", {4}).data, r.label);
  EXPECT_EQ(f.read<double>("/points/position", {2, 3}).data, r.position);
  EXPECT_EQ(f.read<std::int32_t>("/rows/id", {3}).data, (std::vector<std::int32_t>{7, 8, 9}));
  EXPECT_EQ(f.read<float>("/rows/weight", {3}).data, (std::vector<float>{0.5f, 1.5f, 2.5f}));
  // attributes: integers and bools as int64, floating point as float64, strings, arrays
  EXPECT_EQ(f.attr_int("/", "level"), 3);
  EXPECT_EQ(f.attr_int("/", "interior"), 2);
  EXPECT_EQ(f.attr_double("/", "low"), 0.25);
  EXPECT_EQ(f.attr_int("/", "closed"), 1);
  EXPECT_EQ(f.attr_string("/", "note"), "all of it");
  EXPECT_EQ(f.attr_doubles("/", "box"), r.box);
  EXPECT_EQ(f.attr_int("/cells", "occluders"), 4);  // written whatever show_when says
  // empty optionals are not written; a count is not in the file
  EXPECT_FALSE(f.has_attr("/points", "measured"));
  EXPECT_FALSE(f.has("/cells/extra"));
  EXPECT_FALSE(f.has_attr("/", "rows"));
  // a group's table, paths relative to the group; an empty optional group is left out
  EXPECT_EQ(f.read<std::int64_t>("/cache/offsets", {3}).data, r.cache.offsets);
  EXPECT_EQ(f.attr_string("/cache", "signature"), "sig-1");
  EXPECT_EQ(f.attr_double("/cache", "scale"), 1.23456);
  EXPECT_FALSE(f.has("/eval"));
  fs::remove_all(p.parent_path());
}

TEST(H5Fields, OptionalRowsAreWrittenWhenTheyHoldAValue) {
  const fs::path p = fields_file("optional");
  FieldsResult r = sample_result();
  r.measured = 0.75;
  r.extra = std::vector<float>{1, 2, 3, 4};
  r.eval = FieldsPart{{1}, "e", 2.0};
  {
    auto f = h5::File::create(p);
    result_table().write(f, r);
    f.commit();
  }
  const auto f = h5::File::open(p);
  EXPECT_EQ(f.attr_double("/points", "measured"), 0.75);
  EXPECT_EQ(f.read<float>("/cells/extra", {4}).data, (std::vector<float>{1, 2, 3, 4}));
  EXPECT_EQ(f.read<std::int64_t>("/eval/offsets", {1}).data, (std::vector<std::int64_t>{1}));
  EXPECT_EQ(f.attr_string("/eval", "signature"), "e");
  fs::remove_all(p.parent_path());
}

TEST(H5Fields, SummaryLineShowsTheMarkedRowsInTableOrder) {
  FieldsResult r = sample_result();
  EXPECT_EQ(result_table().summary(r),
            "level=3 rows=3 inside=2 low=0.25; shape: closed=1 ratio=2/4 scale=1.23");
  r.occluded = true;
  r.measured = 0.123456789;
  r.eval = FieldsPart{{}, "", 0.5};
  EXPECT_EQ(result_table().summary(r),
            "level=3 rows=3 inside=2 low=0.25; shape: closed=1 measured=0.123457 occluders=4 ratio=2/4 "
            "scale=1.23 scale=0.50");
  // when() leaves a row out of the line (and the file)
  r.label.clear();
  EXPECT_EQ(result_table().summary(r).find("ratio="), std::string::npos);
}

TEST(H5Fields, RowsOfAFixedWidthMustFill) {
  const fs::path p = fields_file("cols");
  FieldsResult r = sample_result();
  r.position.push_back(6);  // 7 values are not rows of 3
  {
    auto f = h5::File::create(p);
    EXPECT_THROW(result_table().write(f, r), Error);
  }  // (not committed: removed)
  EXPECT_FALSE(fs::exists(p));
  fs::remove_all(p.parent_path());
}

TEST(H5Fields, ShowNeedsAnAttributeOrACount) {
  EXPECT_THROW(h5::Fields<FieldsResult>().dataset("/x", &FieldsResult::label).show(), Error);
  EXPECT_THROW(h5::Fields<FieldsResult>().text("a").show(), Error);
}

namespace {

struct ShapedResult {
  std::vector<std::array<std::int32_t, 4>> cells;
  std::vector<std::string> names;
  std::optional<h5::Array<std::uint8_t>> image;
  std::array<double, 3> origin{};
  std::vector<std::array<std::int32_t, 4>> no_cells;
};

h5::Fields<ShapedResult> shaped_table() {
  using R = ShapedResult;
  return h5::Fields<R>()
      .dataset("/cells", &R::cells)
      .dataset("/names", &R::names)
      .dataset("/image", &R::image)
      .dataset("/empty", &R::no_cells)
      .attr("/", "origin", &R::origin);
}

}  // namespace

TEST(H5Fields, ArrayRowsStringsAndShapedArrays) {
  const fs::path p = fields_file("shaped");
  ShapedResult r;
  r.cells = {{0, 1, 2, 3}, {4, 5, 6, 7}, {8, 9, 10, 11}};
  r.names = {"a", "bc", ""};
  r.image = h5::Array<std::uint8_t>{{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12}, {2, 2, 3}};
  r.origin = {0.5, -1, 2};
  {
    auto f = h5::File::create(p);
    shaped_table().write(f, r);
    f.commit();
  }
  {
    const auto f = h5::File::open(p);
    // std::array<T, K> rows: (n, K) of T
    EXPECT_EQ(f.read<std::int32_t>("/cells", {3, 4}).data, (std::vector<std::int32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}));
    EXPECT_EQ(f.read_strings("/names"), r.names);
    // an h5::Array keeps its shape
    EXPECT_EQ(f.read<std::uint8_t>("/image", {2, 2, 3}).data, r.image->data);
    EXPECT_EQ(f.shape_of("/empty"), (h5::Shape{0, 4}));
    // a std::array attribute: float64 values
    EXPECT_EQ(f.attr_doubles("/", "origin"), (std::vector<double>{0.5, -1, 2}));
  }
  // an h5::Array whose data does not fill its shape is refused; an empty optional is left out
  r.image->shape = {2, 2, 2};
  {
    auto f = h5::File::create(p);
    EXPECT_THROW(shaped_table().write(f, r), Error);
  }
  r.image.reset();
  {
    auto f = h5::File::create(p);
    shaped_table().write(f, r);
    f.commit();
  }
  EXPECT_FALSE(h5::File::open(p).has("/image"));
  fs::remove_all(p.parent_path());
}
