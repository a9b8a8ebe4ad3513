// The triangular lattice of a face and its implicit quad-tree (paper section 2.3).
//
// A face (a, b, c) with n divisions carries the (n+1)(n+2)/2 points
// a + (i/n)(b - a) + (j/n)(c - a), i, j >= 0, i + j <= n, stored in order of j then i
// (photo/lattice.h triangle_lattice). When n is even, the lattice of each quarter of the
// face (the three corner quarters and the middle one: the faces red refinement makes in
// it) is exactly the sub-lattice with n/2 divisions; recursively, a lattice with
// n = c 2^e divisions is a complete quad-tree of depth e whose leaves are lattice points.
// The stage stores only the leaves (one 16-bit code per point, see encode_point): the
// counts of any node (a descendant face) are sums over its sub-lattice, and its best
// point is the best code in it. Storing counts and best points at every node instead
// would take more room than the leaves (4/3 4^e nodes vs 4^e/2 points).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "common/photo/oriented_point.h"

namespace tetmvs::photoconsist {

inline std::int64_t lattice_size(int n) { return static_cast<std::int64_t>(n + 1) * (n + 2) / 2; }
inline std::int64_t lattice_index(int n, int i, int j) {
  return static_cast<std::int64_t>(j) * (n + 1) - static_cast<std::int64_t>(j) * (j - 1) / 2 + i;
}

// Divisions actually used for a face that needs `need` (>= 1): the smallest number
// >= need of the form 2^e or 3 * 2^e, so that the lattice halves exactly over several
// levels (48 -> 24 -> 12 -> 6 -> 3), at most 3/2 of the need (2^e + 1 -> 3 2^(e-1)).
int reusable_divisions(int need);

// One 16-bit code per lattice point:
//   0                outside the visual hull (not a sample)
//   1                inside the hull, no score (fewer than k'+1 usable views)
//   2 .. 0x7fff      the score, quantized: 2 + round((score + 1) / 2 * 32765)
//   bit 15 (0x8000)  set when the point is photo-consistent (score > T, decided exactly)
inline constexpr std::uint16_t kCodeOutside = 0;
inline constexpr std::uint16_t kCodeNoScore = 1;
inline constexpr std::uint16_t kCodeConsistent = 0x8000;
std::uint16_t encode_point(const photo::PointResult& r, const photo::Options& opts);
inline bool code_is_sample(std::uint16_t c) { return c != kCodeOutside; }
inline bool code_is_consistent(std::uint16_t c) { return (c & kCodeConsistent) != 0; }
// The quantized score (kNoScore for codes 0 and 1).
float code_score(std::uint16_t c);
// Order of the codes for the best point: consistent first, then by quantized score.
inline std::uint16_t code_rank(std::uint16_t c) { return c; }

// Lattice coordinates (3 ints) of a face's three vertices, in its vertex order.
using FaceLat = std::array<std::int32_t, 9>;

// When the triangle `child` (lattice coordinates of its vertices, its own order) is the
// same triangle as `parent` or one of its four quarters, and parent_n allows it (even for
// a quarter), writes the child's divisions (parent_n or parent_n / 2) to *child_n and, for
// every point of the child's lattice in its order, the index of the same point in the
// parent's lattice to `index`; returns true. Returns false otherwise.
bool map_sub_lattice(const FaceLat& parent, int parent_n, const FaceLat& child, int* child_n,
                     std::vector<std::int64_t>& index);

}  // namespace tetmvs::photoconsist
