// Z-buffer rasteriser of a triangle mesh seen by a Camera: depth map (camera z),
// triangle-id map and coverage.
//
// Sampling is exact at sample points: with supersampling s, the sample (i, j) of the
// (s*W) x (s*H) grid sits at continuous pixel coordinate ((i + 0.5)/s - 0.5, (j + 0.5)/s - 0.5),
// so with s = 1 the samples are the pixel centres (u, v). A sample is covered by a
// triangle when it is strictly inside, or on an edge that is a top or left edge (D3D
// top-left rule), so triangles sharing an edge cover each sample on it exactly once.
// Vertex positions are snapped to 1/256 of a sample for exact integer edge tests.
// Nearest depth wins (ties: lower triangle id). Depth is perspective-correct.
// Triangles with a vertex at camera depth <= znear are skipped and counted.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>

#include "common/camera.h"
#include "common/trimesh/trimesh.h"

namespace tetmvs {

// std::llround (halves away from zero) without the library call; |x| < 2^62.
inline std::int64_t round_nearest(double x) {
  const auto t = static_cast<std::int64_t>(x);  // towards zero
  const double r = x - static_cast<double>(t);   // exact
  return t + static_cast<std::int64_t>(r >= 0.5) - static_cast<std::int64_t>(r <= -0.5);  // no branch
}

struct RasterOptions {
  int supersample = 1;      // s >= 1
  double znear = 1e-9;      // triangles with a vertex at depth <= znear are skipped
  bool cull_back = false;   // skip triangles whose front (counter-clockwise seen from outside) faces away
};

struct Raster {
  int width = 0, height = 0, ss = 1;  // image size in pixels; the buffers are (ss*H) x (ss*W)
  cv::Mat depth;  // CV_32F, camera z of the nearest surface, +inf where empty
  cv::Mat tri;    // CV_32S, triangle id, -1 where empty
  std::int64_t skipped_near = 0;  // triangles dropped by znear
  cv::Rect covered_box;           // the buffer samples a triangle covers (empty: none)

  // Continuous pixel coordinate of buffer sample (i, j).
  double sample_u(int i) const { return (i + 0.5) / ss - 0.5; }
  double sample_v(int j) const { return (j + 0.5) / ss - 0.5; }
  // Coverage fraction per pixel (CV_32F in [0,1]).
  cv::Mat coverage() const;
  // CV_8U mask, 255 where the pixel centre is covered (needs an odd ss).
  cv::Mat centre_mask() const;
};

// Camera width/height must be set (> 0).
Raster rasterize(const TriMesh& m, const Camera& cam, const RasterOptions& opt = {});

// The raster of the same camera with the first two rows of K divided by 2^level and the
// image halved (rounding up) level times (a pyramid level): its pixel (x, y) sees along the
// ray of r's pixel (x 2^level, y 2^level), whose depth and triangle it takes. Equal to
// rasterising at that level up to the snapping of vertices (1/256 of a sample) on samples
// that lie on a triangle's edge. Needs r.ss == 1.
Raster subsample(const Raster& r, int level);

// World point on triangle f under continuous pixel (u, v) (ray-plane intersection).
// Returns false when the ray is parallel to the triangle plane.
bool pixel_point_on_triangle(const TriMesh& m, int f, const Camera& cam, double u, double v,
                             Eigen::Vector3d& X);

}  // namespace tetmvs
