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

}  // namespace tetmvs::deform
