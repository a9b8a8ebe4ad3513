// An output file declared as a table: one row per dataset or attribute, each with the getter
// that takes its value from the stage's result. write() writes the rows in table order;
// summary() makes the stage's `key=value` summary line (scripts/bench_pipeline.py reads it)
// from the rows marked with show(). A field is named once, and the file and the summary line
// agree by construction; schemas/ documents the same names.
//
//   const h5::Fields<Result> table = h5::Fields<Result>()
//       .dataset("/cells/label", &Result::label)             // std::vector<T>: (n,)
//       .dataset("/points/position", &Result::position, 3)  // (n / 3, 3)
//       .attr("/", "interior", &Result::interior).show()     // "interior=12"
//       .attr("/", "low_votes", &Result::low_votes);
//   table.write(file, r);           // after file.write_header(...), before file.commit()
//   summary = table.summary(r);
//
// Getters are member pointers or callables taking the result (by const reference). What a
// getter returns decides what is written: a std::vector of a numeric type a dataset (a
// std::vector of std::array<T, K> one of K columns, a std::vector<std::string> a string
// dataset, an h5::Array<T> a dataset of its own shape); an integer or bool an int64
// attribute, a floating-point value a float64 one, a string a string one, a
// std::vector<double> or a std::array of numbers a float64 array. A std::optional is written (and shown)
// only when it holds a value. group() writes a part of the result with its own table under
// a group (a std::optional part only when present). count() and text() add to the summary
// line only: counts the file does not store, and the line's headings.
//
// Summary line: `key=value` per shown row, separated by spaces; text() is appended as it is
// ("; cells by rule:"). Numbers print as std::ostream prints them (or with a fixed number
// of decimals, show(key, decimals)).
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <iomanip>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/error.h"
#include "common/h5io.h"

namespace tetmvs::h5 {

// One member of every row as a flat vector: the data of one column dataset.
template <typename Row, typename M>
std::vector<M> column(const std::vector<Row>& rows, M Row::*member) {
  std::vector<M> out;
  out.reserve(rows.size());
  for (const auto& r : rows) out.push_back(r.*member);
  return out;
}

namespace fields_detail {

template <typename T>
struct is_optional : std::false_type {};
template <typename T>
struct is_optional<std::optional<T>> : std::true_type {};

template <typename T>
struct is_vector : std::false_type {};
template <typename T, typename A>
struct is_vector<std::vector<T, A>> : std::true_type {};

template <typename T>
struct is_std_array : std::false_type {};
template <typename T, std::size_t K>
struct is_std_array<std::array<T, K>> : std::true_type {};

template <typename T>
struct is_h5_array : std::false_type {};
template <typename T>
struct is_h5_array<Array<T>> : std::true_type {};

// Writes a dataset's value: a std::vector (of numbers: shape (n,) or (n / cols, cols); of
// std::array<T, K>: (n, K); of strings: (n,)) or an h5::Array (its shape).
template <typename V>
void write_dataset(File& f, const std::string& name, const V& v, std::uint64_t cols) {
  if constexpr (is_h5_array<V>::value) {
    std::uint64_t total = 1;
    for (const auto d : v.shape) total *= d;
    require(!v.shape.empty() && total == v.data.size(), f.path().string(), ": ", name, " holds ", v.data.size(),
            " values, not the ", total, " of its shape");
    f.write(name, v.data.data(), v.shape);
  } else {
    static_assert(is_vector<V>::value, "a dataset's getter returns a std::vector or an h5::Array");
    using T = typename V::value_type;
    if constexpr (std::is_same_v<T, std::string>) {
      f.write_strings(name, v);
    } else if constexpr (is_std_array<T>::value) {
      using E = typename T::value_type;
      static_assert(std::is_arithmetic_v<E> && sizeof(T) == std::tuple_size_v<T> * sizeof(E));
      require(cols == 1, f.path().string(), ": ", name, ": rows of std::array take their columns from it");
      f.write(name, v.empty() ? static_cast<const E*>(nullptr) : v.front().data(),
              {v.size(), std::tuple_size_v<T>});
    } else {
      require(cols > 0 && v.size() % cols == 0, f.path().string(), ": ", name, " holds ", v.size(),
              " values, not rows of ", cols);
      if (cols == 1)
        f.write(name, v, {v.size()});
      else
        f.write(name, v, {v.size() / cols, cols});
    }
  }
}

// Calls f(value) with the getter's value, or not at all for an empty std::optional.
template <typename V, typename F>
void with_value(const V& v, F&& f) {
  if constexpr (is_optional<V>::value) {
    if (v) f(*v);
  } else {
    f(v);
  }
}

inline std::string join(const std::string& base, const std::string& rel) {
  if (base.empty()) return rel;
  if (rel.empty()) return base;
  return base + "/" + rel;
}

template <typename V>
void write_attr(File& f, const std::string& obj, const std::string& name, const V& v) {
  if (!f.has(obj)) f.create_group(obj);
  if constexpr (std::is_same_v<V, bool> || std::is_integral_v<V>)
    f.set_attr(obj, name, static_cast<std::int64_t>(v));
  else if constexpr (std::is_floating_point_v<V>)
    f.set_attr(obj, name, static_cast<double>(v));
  else if constexpr (std::is_same_v<V, std::vector<double>>)
    f.set_attr(obj, name, v);
  else if constexpr (is_std_array<V>::value)
    f.set_attr(obj, name, std::vector<double>(v.begin(), v.end()));
  else
    f.set_attr(obj, name, std::string(v));
}

template <typename V>
std::string text_of(const V& v, int decimals) {
  std::ostringstream os;
  if constexpr (std::is_same_v<V, bool>) {
    os << (v ? 1 : 0);
  } else if constexpr (std::is_floating_point_v<V>) {
    if (decimals >= 0) os << std::fixed << std::setprecision(decimals);
    os << v;
  } else if constexpr (std::is_integral_v<V>) {
    os << +v;  // (a char-sized integer prints as a number)
  } else {
    os << v;
  }
  return os.str();
}

}  // namespace fields_detail

template <typename R>
class Fields {
 public:
  // A dataset at `path` from a getter returning a std::vector<T>; shape (n,), or (n / cols,
  // cols) for cols > 1; (n, K) for a std::vector<std::array<T, K>>; an h5::Array<T>'s shape.
  template <typename Get>
  Fields& dataset(std::string path, Get get, std::uint64_t cols = 1) {
    Row row;
    row.name = path;
    row.write = [path, get, cols](File& f, const R& r, const std::string& base) {
      fields_detail::with_value(std::invoke(get, r), [&](const auto& v) {
        fields_detail::write_dataset(f, fields_detail::join(base, path), v, cols);
      });
    };
    rows_.push_back(std::move(row));
    return *this;
  }

  // An attribute `name` of the object at `obj` ("/" the root; in a group's table, "" the
  // group). The object is made as a group when it does not exist yet.
  template <typename Get>
  Fields& attr(std::string obj, std::string name, Get get) {
    Row row;
    row.name = name;
    row.write = [obj, name, get](File& f, const R& r, const std::string& base) {
      const std::string o = fields_detail::join(base, obj);
      fields_detail::with_value(std::invoke(get, r), [&](const auto& v) {
        fields_detail::write_attr<std::decay_t<decltype(v)>>(f, o.empty() ? "/" : o, name, v);
      });
    };
    row.value = value_of(get);
    rows_.push_back(std::move(row));
    return *this;
  }

  // A part of the result written with its own table under the group `path` (the sub-table's
  // paths are relative to it). Its shown rows join this table's summary line.
  template <typename S, typename Get>
  Fields& group(std::string path, Get get, Fields<S> sub) {
    Row row;
    row.name = path;
    row.write = [path, get, sub](File& f, const R& r, const std::string& base) {
      fields_detail::with_value(std::invoke(get, r), [&](const S& s) {
        const std::string g = fields_detail::join(base, path);
        f.create_group(g);
        sub.write(f, s, g);
      });
    };
    row.append = [get, sub](const R& r, std::string& line) {
      fields_detail::with_value(std::invoke(get, r), [&](const S& s) { sub.append_summary(s, line); });
    };
    rows_.push_back(std::move(row));
    return *this;
  }

  // A count the summary line shows as `key=value` and the file does not store.
  template <typename Get>
  Fields& count(std::string key, Get get) {
    Row row;
    row.name = key;
    row.value = value_of(get);
    row.key = std::move(key);
    rows_.push_back(std::move(row));
    return *this;
  }

  // Text appended to the summary line as it is (a heading such as "; cells by rule:").
  Fields& text(std::string t) {
    Row row;
    row.append = [t](const R&, std::string& line) { line += t; };
    rows_.push_back(std::move(row));
    return *this;
  }

  // The last attribute appears in the summary line as key=value (key: the attribute's name
  // unless given; decimals >= 0: floating-point values with that many decimals).
  Fields& show(std::string key = "", int decimals = -1) {
    require(!rows_.empty() && rows_.back().value, "h5::Fields::show: the last row is not an attribute or a count");
    rows_.back().key = key.empty() ? rows_.back().name : std::move(key);
    rows_.back().decimals = decimals;
    return *this;
  }

  // The last row is written and shown only when pred(result) holds.
  Fields& when(std::function<bool(const R&)> pred) {
    require(!rows_.empty(), "h5::Fields::when: no row");
    rows_.back().when = std::move(pred);
    return *this;
  }

  // The last row is shown only when pred(result) holds (it is written regardless).
  Fields& show_when(std::function<bool(const R&)> pred) {
    require(!rows_.empty(), "h5::Fields::show_when: no row");
    rows_.back().show_when = std::move(pred);
    return *this;
  }

  // Writes every row in order; `base` prefixes the paths (a group's table).
  void write(File& f, const R& r, const std::string& base = "") const {
    for (const auto& row : rows_)
      if (row.write && (!row.when || row.when(r))) row.write(f, r, base);
  }

  // The summary line of the shown rows.
  std::string summary(const R& r) const {
    std::string line;
    append_summary(r, line);
    return line;
  }

  // Appends the shown rows to `line` (a space before each key=value unless the line is empty).
  void append_summary(const R& r, std::string& line) const {
    for (const auto& row : rows_) {
      if ((row.when && !row.when(r)) || (row.show_when && !row.show_when(r))) continue;
      if (row.append) {
        row.append(r, line);
      } else if (!row.key.empty()) {
        const std::optional<std::string> v = row.value(r, row.decimals);
        if (!v) continue;
        if (!line.empty()) line += ' ';
        line += row.key + "=" + *v;
      }
    }
  }

 private:
  struct Row {
    std::string name;  // dataset path, attribute name, group path or count key
    std::function<void(File&, const R&, const std::string&)> write;                 // empty: not in the file
    std::function<std::optional<std::string>(const R&, int decimals)> value;       // a scalar's text
    std::function<void(const R&, std::string&)> append;                            // text, a group's rows
    std::string key;  // non-empty: shown as key=value
    int decimals = -1;
    std::function<bool(const R&)> when, show_when;
  };

  template <typename Get>
  static std::function<std::optional<std::string>(const R&, int)> value_of(Get get) {
    return [get](const R& r, int decimals) -> std::optional<std::string> {
      std::optional<std::string> out;
      fields_detail::with_value(std::invoke(get, r), [&](const auto& v) {
        using V = std::decay_t<decltype(v)>;
        if constexpr (fields_detail::is_vector<V>::value || fields_detail::is_std_array<V>::value ||
                      fields_detail::is_h5_array<V>::value)
          out.reset();  // arrays are not shown
        else
          out = fields_detail::text_of(v, decimals);
      });
      return out;
    };
  }

  std::vector<Row> rows_;
};

}  // namespace tetmvs::h5
