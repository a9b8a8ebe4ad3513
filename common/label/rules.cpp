#include "common/label/rules.h"

#include <bit>

#include "common/error.h"

namespace tetmvs::label {

static_assert(kNumRules <= 16, "Proposals holds 16 rules");

namespace {
constexpr bool table_in_enum_order() {
  for (int i = 0; i < kNumRules; ++i)
    if (static_cast<int>(kRules[i].rule) != i) return false;
  return true;
}
static_assert(table_in_enum_order(), "kRules must list the rules in the order of enum Rule");
}  // namespace

void Proposals::add(Rule r, const std::vector<std::uint8_t>& cells) {
  require(cells.size() == bits_.size(), "label: rule ", info(r).name, " proposes ", cells.size(), " flags for ",
          bits_.size(), " cells");
  for (std::size_t c = 0; c < cells.size(); ++c)
    if (cells[c]) add(r, static_cast<std::int32_t>(c));
}

int Proposals::winner(std::int32_t c) const { return bits_[c] == 0 ? -1 : std::countr_zero(bits_[c]); }

Decision decide(const Proposals& p) {
  const std::int32_t C = p.size();
  Decision d;
  d.label.assign(C, 0);
  d.reason.assign(C, kNone);
  d.rule.assign(C, -1);
  for (std::int32_t c = 0; c < C; ++c) {
    const int w = p.winner(c);
    if (w < 0) continue;
    d.rule[c] = static_cast<std::int8_t>(w);
    d.label[c] = kRules[w].label;
    d.reason[c] = kRules[w].reason;
    ++d.cells[w];
    d.interior += d.label[c] > 0;
    d.exterior += d.label[c] < 0;
  }
  return d;
}

}  // namespace tetmvs::label
