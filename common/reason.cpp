#include "common/reason.h"

#include <iterator>

namespace tetmvs {

namespace {
struct ReasonInfo {
  const char* name;
  int label;
};
constexpr ReasonInfo kReasonInfo[kNumReasons] = {
    {"none", 0},        {"boundary", -1},       {"outside_hull", -1},   {"voted_out", -1},
    {"hidden", 1},      {"silfix_exterior", -1}, {"silfix_interior", 1}, {"hull_core", 1},
    {"outside_q_hull", -1}, {"seed_core", 1},   {"seen_free", -1},
};
static_assert(std::size(kReasonInfo) == kNumReasons);
}  // namespace

const char* reason_name(int reason) { return reason >= 0 && reason < kNumReasons ? kReasonInfo[reason].name : "unknown"; }

int reason_label(int reason) { return reason >= 0 && reason < kNumReasons ? kReasonInfo[reason].label : 0; }

}  // namespace tetmvs
