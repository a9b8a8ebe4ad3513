// Small geometric helpers shared by label's files: pixels of points, and the mesh's vertex
// and cell positions computed once (and per view, the vertices' projections), so that the
// per-view tests over millions of cells project each vertex once.
#pragma once
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/camera.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs::label {

// The nearest integer to a pixel coordinate, halves away from zero (as std::lround, without
// the library call); a value far outside any image (INT_MIN) beyond +-1e9 and for NaN.
inline int round_px(double x) {
  if (!(x > -1e9 && x < 1e9)) return std::numeric_limits<int>::min();
  const auto i = static_cast<std::int64_t>(x);     // toward zero
  const double f = x - static_cast<double>(i);      // exact
  return static_cast<int>(i + (f >= 0.5) - (f <= -0.5));
}

// X's depth z in cam and the pixel (u, w) nearest to its projection; false when X is not in
// front of the camera or the pixel lies outside the image.
inline bool nearest_pixel(const Camera& cam, const Eigen::Vector3d& X, double& z, int& u, int& w) {
  z = cam.depth(X);
  if (z <= 0) return false;
  const Eigen::Vector2d p = cam.project(X);
  u = round_px(p.x());
  w = round_px(p.y());
  return u >= 0 && w >= 0 && u < cam.width && w < cam.height;
}

// World positions of the mesh's vertices and of its cells' centroids (as TetMesh::vertex and
// TetMesh::cell_centroid give them, bit for bit).
struct MeshPoints {
  std::vector<Eigen::Vector3d> vertex, centroid;
  explicit MeshPoints(const tet::TetMesh& m);
};

// One view's projection of every vertex: its pixel (valid only where z > 0) and depth.
struct VertexProjection {
  std::vector<Eigen::Vector2d> px;
  std::vector<double> z;
  void compute(const Camera& cam, const MeshPoints& pts);
};

}  // namespace tetmvs::label
