// The silhouettes' tests on cells and points (paper 2.4, and the hull-core prior): each view
// is taken in turn and every vertex projected once (geometry.h).
#pragma once
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "common/label/geometry.h"
#include "common/scene.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs::label {

// Per view with a silhouette, the distance (pixels) from each pixel inside it to the nearest
// pixel outside (empty Mat for views without one).
std::vector<cv::Mat> silhouette_distances(const Scene& s);

// Per cell: 1 when the cell is surely outside the visual hull: in some view with a
// silhouette the whole projected cell (a disc around it, grown by 1.5 px for the pixel
// rounding) lies inside the image and outside the silhouette. Parts outside an image never
// carve.
std::vector<std::uint8_t> outside_visual_hull(const tet::TetMesh& m, const Scene& s);
std::vector<std::uint8_t> outside_visual_hull(const tet::TetMesh& m, const MeshPoints& pts, const Scene& s);

// Cells whose whole projection lies at least core_px pixels inside the silhouette in every
// view with a silhouette it projects into (and at least min_views such views), among the
// cells whose flag in `skip` is 0. dist: silhouette_distances().
std::vector<std::uint8_t> hull_core_cells(const tet::TetMesh& m, const MeshPoints& pts, const Scene& s,
                                          const std::vector<cv::Mat>& dist, const std::vector<std::uint8_t>& skip,
                                          double core_px, int min_views);

// Per vertex: 1 when it projects inside the silhouette of every view with a silhouette that
// it lies in front of (outside an image counts as inside).
std::vector<std::uint8_t> vertices_in_silhouettes(const MeshPoints& pts, const Scene& s);

// True when X projects at least depth_px pixels inside the silhouette of every view with a
// silhouette whose image it falls in (dist: silhouette_distances()).
bool deep_in_hull(const Scene& s, const std::vector<cv::Mat>& dist, const Eigen::Vector3d& X, double depth_px);

// The world size of a pixel at the object: the median over the views of the depth of the
// scene box's centre over the focal length.
double pixel_size(const Scene& s);

// True when X projects at least `margin` pixels inside the silhouette of every view with a
// silhouette whose image it falls in, and there is at least one such view.
bool in_hull_core(const Scene& s, const std::vector<cv::Mat>& dist, const Eigen::Vector3d& X, double margin);

}  // namespace tetmvs::label
