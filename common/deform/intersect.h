// Self-intersection test of a triangle mesh (deform's safety check): pairs of triangles
// that cross each other. Triangles sharing an edge are never tested (they can only
// overlap when coplanar); triangles sharing one vertex intersect when the edge opposite
// the shared vertex of one crosses the other; others when any edge of one crosses the
// interior of the other. Crossings are strict (touching at a point, e.g. the coincident
// vertex copies of the cut's split sheets, does not count). Candidate pairs come from a
// uniform grid of face boxes (cells about one face wide), built over all faces, or over
// the flagged faces only when they are few. Deterministic, OpenMP.
#pragma once
#include <Eigen/Dense>
#include <utility>
#include <vector>

namespace tetmvs::deform {

// True when segment pq crosses the interior of triangle abc (strictly).
bool segment_crosses_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// Intersecting pairs (f < g), sorted. When only_faces is non-empty, only pairs with at
// least one face flagged in it are reported (faces not flagged are still tested against
// flagged ones).
std::vector<std::pair<int, int>> self_intersections(const std::vector<Eigen::Vector3d>& V,
                                                    const std::vector<Eigen::Vector3i>& F,
                                                    const std::vector<char>& only_faces = {});

// The face pairs that can intersect while every vertex moves on the segment from V0[v] to
// V1[v] (e.g. a step scaled down by retries): those whose boxes, each taken over both end
// states, overlap; pairs sharing an edge are left out. Built once with the grid, then each
// test of a state between the two only tests the stored pairs: a retry that changes few
// faces costs a pass over the list, not a grid. F must outlive the object.
class MotionPairs {
 public:
  MotionPairs(const std::vector<Eigen::Vector3d>& V0, const std::vector<Eigen::Vector3d>& V1,
              const std::vector<Eigen::Vector3i>& F);
  // Intersecting pairs (f < g, sorted) of V, whose vertices must lie on their segments;
  // with only_faces, the pairs with a flagged face only (as self_intersections).
  std::vector<std::pair<int, int>> intersections(const std::vector<Eigen::Vector3d>& V,
                                                 const std::vector<char>& only_faces = {}) const;
  std::size_t size() const { return pairs_.size(); }

 private:
  const std::vector<Eigen::Vector3i>& F_;
  std::vector<std::pair<int, int>> pairs_;  // f < g, sorted
};

}  // namespace tetmvs::deform
