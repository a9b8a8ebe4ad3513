// Measuring the photoconsist stage against a ground-truth surface (synth's gt.ply):
// which faces the true surface crosses, how far faces and points are from it. Used by
// the stage's --gt option, the tests and the tuning in docs/photoconsist.md.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "common/photoconsist/level_pass.h"
#include "common/trimesh/bvh.h"
#include "common/trimesh/trimesh.h"

namespace tetmvs::photoconsist {

class GroundTruth {
 public:
  // gt: a closed triangle mesh.
  explicit GroundTruth(const TriMesh& gt);
  // Inside the closed surface: parity of ray crossings, majority of three rays.
  bool inside(const Eigen::Vector3d& X) const;
  double distance(const Eigen::Vector3d& X) const { return bvh_.closest(X).dist(); }
  double scale() const { return scale_; }
  const MeshBVH& bvh() const { return bvh_; }

 private:
  int crossings(const Eigen::Vector3d& X, const Eigen::Vector3d& d) const;
  MeshBVH bvh_;
  double scale_ = 1;  // bounding-box diagonal
};

struct LevelEval {
  double near_dist = 0;           // "near the surface": within this distance (2 cell sizes)
  std::int64_t tested = 0;        // faces tested
  std::int64_t gt_crossed = 0;    // tested faces whose vertices lie on both sides of the GT surface
  std::int64_t found = 0;         // of those, found crossing
  std::int64_t crossing = 0;      // faces found crossing
  std::int64_t crossing_near = 0; // of those, within near_dist of the GT surface
  std::int64_t cells_gt = 0;      // tested cells (cell_new_red) with corners on both sides
  std::int64_t cells_found = 0;   // of those, active
  std::int64_t active = 0;        // active cells
  std::int64_t active_far = 0;    // of those, with no tested face within near_dist of the GT surface
  std::int64_t active_far_air = 0;  // of those, with the centroid outside the GT surface (free space)
  std::int64_t points = 0;        // Q points of the level
  std::int64_t points_near = 0;   // within one cell size (near_dist / 2) of the GT surface
  double recall() const { return gt_crossed ? static_cast<double>(found) / gt_crossed : 1.0; }
  double precision() const { return crossing ? static_cast<double>(crossing_near) / crossing : 1.0; }
  double cell_recall() const { return cells_gt ? static_cast<double>(cells_found) / cells_gt : 1.0; }
  double points_accuracy() const { return points ? static_cast<double>(points_near) / points : 1.0; }
  // Share of the active cells that lie away from the surface: work the next level spends for nothing.
  double active_far_share() const { return active ? static_cast<double>(active_far) / active : 0.0; }
  // Per tested face (same order as LevelResult::face).
  std::vector<std::uint8_t> face_gt_crossed;
  std::vector<float> face_gt_distance;  // 0 when crossed; else min distance of 7 samples (vertices, edge midpoints, centroid)
};

// cell_size: the level's cell size (tet::red_edge_length(lat, level)); near = 2 cell sizes.
LevelEval evaluate_level(const tet::TetMesh& m, const LevelResult& r, const GroundTruth& gt, double cell_size);

// Fraction of points of q within dist of the GT surface.
double fraction_within(const QPoints& q, const GroundTruth& gt, double dist);

}  // namespace tetmvs::photoconsist
