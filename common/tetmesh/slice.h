// A picture of the mesh: the cells cut by an axis-aligned plane, each filled with a
// colour (by level, or by any per-cell field such as labels), like Fig. 1(b) of the paper.
#pragma once
#include <opencv2/core.hpp>
#include <vector>

#include "common/tetmesh/tetmesh.h"

namespace tetmvs::tet {

struct SliceSpec {
  int axis = 2;              // plane normal: 0 x, 1 y, 2 z
  double position = 0.0;     // world coordinate of the plane along `axis`
  int width = 1024;          // image width in pixels (height follows the box aspect)
  bool edges = true;         // draw cell outlines (dark) when cells are >= 4 px
};

// RGB image (CV_8UC3): horizontal = axis+1, vertical = axis+2 (upward); outside the mesh
// is white. `colours` has one RGB colour per cell.
cv::Mat render_slice(const TetMesh& m, const SliceSpec& s, const std::vector<cv::Vec3b>& colours);

// Colours: by refinement level (red cells; green cells a lighter shade of their level),
// by a scalar field through a blue-to-red ramp on [lo, hi], by integer labels.
std::vector<cv::Vec3b> colours_by_level(const TetMesh& m);
std::vector<cv::Vec3b> colours_by_field(const std::vector<double>& v, double lo, double hi);
std::vector<cv::Vec3b> colours_by_label(const std::vector<int>& labels);

}  // namespace tetmvs::tet
