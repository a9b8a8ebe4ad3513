// Test sizes under the sanitizers. The ASan + UBSan pass of CI (scripts/test.sh) runs the
// unit tests about 10x slower than the Release pass; randomised tests that repeat one check
// many times use fewer repetitions there (the Release pass keeps the full count).
#pragma once

namespace tetmvs::test {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif

// `full` repetitions in a normal build, `sanitized` under the sanitizers.
inline constexpr int reps(int full, int sanitized) { return kSanitized ? sanitized : full; }

}  // namespace tetmvs::test
