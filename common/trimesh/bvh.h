// Bounding-volume hierarchy over the triangles of a mesh (or the points of a point
// cloud): closest-point queries and first-hit ray casts. Queries are const and
// thread-safe; build once, query from an OpenMP loop.
#pragma once
#include <Eigen/Core>
#include <limits>
#include <vector>

#include "common/trimesh/trimesh.h"

namespace tetmvs {

// Closest point on triangle abc to p (exact, Voronoi-region method).
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c);

struct ClosestHit {
  double dist2 = std::numeric_limits<double>::infinity();  // squared distance
  int prim = -1;               // face (mesh) or vertex (point cloud); -1 when none within range
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double dist() const { return std::sqrt(dist2); }
};

struct RayHit {
  double t = std::numeric_limits<double>::infinity();  // ray parameter (distance for a unit direction)
  int face = -1;
  double b1 = 0, b2 = 0;  // barycentrics of vertices 1 and 2
};

class MeshBVH {
 public:
  MeshBVH() = default;
  // Triangles of m, or its vertices when m has no faces. Copies what it needs.
  explicit MeshBVH(const TriMesh& m);
  bool points_only() const { return points_only_; }
  std::size_t num_primitives() const { return prims_.size(); }
  // Closest primitive to p within max_dist (infinite = always found unless empty).
  ClosestHit closest(const Eigen::Vector3d& p, double max_dist = std::numeric_limits<double>::infinity()) const;
  // First triangle hit by o + t d with tmin < t < tmax (mesh only; both faces count).
  RayHit raycast(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double tmin = 0,
                 double tmax = std::numeric_limits<double>::infinity()) const;
  // Whether p lies inside the closed mesh (ground truth): the parity of a ray's crossings,
  // majority of three fixed directions (robust to a ray that grazes an edge). Points outside
  // the bounding box are outside. Mesh only.
  bool inside(const Eigen::Vector3d& p) const;

 private:
  struct Node {
    Eigen::Vector3d lo, hi;
    int left = -1, right = -1;  // children, or -1 for a leaf
    int start = 0, count = 0;   // leaf: prims_[start, start+count)
  };
  int build(int start, int end, std::vector<Eigen::Vector3d>& centroids);
  bool points_only_ = false;
  std::vector<Eigen::Vector3d> A, B, C;  // triangle corners (A only for points)
  std::vector<int> prims_;               // primitive ids in leaf order
  std::vector<Node> nodes_;
};

}  // namespace tetmvs
