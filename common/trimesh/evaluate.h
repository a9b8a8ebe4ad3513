// Middlebury-style evaluation of a reconstruction against a ground-truth mesh
// (Seitz et al. CVPR 2006):
//   accuracy      distance d such that `accuracy_fraction` (90 %) of the reconstruction
//                 (area-weighted surface samples, or the points of a point cloud) lies
//                 within d of the ground truth; also 50 %, 95 %, mean, max. Also over the
//                 seen part only: the samples whose closest ground-truth point at least
//                 `min_views` cameras see (Middlebury leaves out the points nearest to the
//                 ground truth's unobserved, hole-filled parts: a cup's bottom);
//   completeness  share of ground-truth surface samples within `threshold` (1.25 mm) of
//                 the reconstruction, counting only samples visible (front-facing,
//                 unoccluded, inside the image) in at least `min_views` cameras.
// Both are also reported per ground-truth region (per-face or per-vertex property
// "region" of the ground truth: 0 body, 1 cavity, 2 protrusion, ...) and, optionally,
// inside a box. Output format: schemas/evaluate.md.
#pragma once
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "common/camera.h"
#include "common/trimesh/bvh.h"
#include "common/trimesh/check.h"
#include "common/trimesh/sample.h"
#include "common/trimesh/trimesh.h"

namespace tetmvs {

struct EvalOptions {
  double spacing = 2e-4;                  // surface sample spacing (world units)
  std::vector<double> thresholds = {0.00125};  // completeness thresholds; the first is the headline
  double accuracy_fraction = 0.9;
  int min_views = 2;
  double visibility_tolerance_px = 2.0;
  std::uint64_t seed = 1;
  std::optional<Eigen::AlignedBox3d> region_box;  // extra region "box"
  void check() const;                     // throws Error on a bad value
};

struct AccuracyStats {
  std::int64_t samples = 0;
  double at_fraction = 0, p50 = 0, p90 = 0, p95 = 0, mean = 0, max = 0;  // meaningless when samples == 0
};

struct CompletenessStats {
  std::int64_t gt_samples = 0;       // all ground-truth samples of the region
  std::int64_t visible_samples = 0;  // those seen by >= min_views cameras (the denominator)
  std::vector<double> within;        // per threshold: share of visible samples within it
  // Headline threshold: share of ALL samples of the region within it (unseen ones count as
  // missed). For a region the cameras cannot see whole (a cup's cavity seen by a ring), the
  // ceiling of this is visible_samples / gt_samples whatever the method.
  double within_all = 0;
};

struct RegionResult {
  std::string name;  // "all", "body", "cavity", "protrusion", "region_<k>", "box"
  int id = -1;       // region label (-1 for "all" and "box")
  CompletenessStats completeness;
  AccuracyStats accuracy;  // reconstruction samples whose closest ground-truth point is in the region
  AccuracyStats accuracy_seen;  // those of them whose closest ground-truth point is seen
};

struct EvalResult {
  EvalOptions options;
  RegionResult all;
  std::vector<RegionResult> regions;  // by label, then "box"
  MeshCheck rec_check, gt_check;
  double rec_area = 0, gt_area = 0;
  bool rec_is_point_cloud = false;
  int num_cameras = 0;
};

// Number of cameras that see each sample (front-facing, inside the image, not occluded
// in the mesh's depth map). Deterministic; OpenMP over cameras.
std::vector<int> count_visible_views(const TriMesh& mesh, const SurfaceSamples& s, const std::vector<Camera>& cams,
                                     double tolerance_px);

// Per-face region label of the ground truth (face property "region", else vertex property
// "region" by majority of the three corners, else all 0).
std::vector<int> face_regions(const TriMesh& gt);

EvalResult evaluate(const TriMesh& rec, const TriMesh& gt, const std::vector<Camera>& cams, const EvalOptions& opt);

nlohmann::json to_json(const EvalResult& r);

// The reconstruction seen from `views` evenly spaced cameras, coloured by distance to the
// ground truth (blue 0 -> green -> yellow -> red >= max_error), shaded by the viewing
// angle, tiled in a grid with a legend. RGB CV_8UC3.
cv::Mat error_picture(const TriMesh& rec, const MeshBVH& gt, const std::vector<Camera>& cams, int views,
                      double max_error);

}  // namespace tetmvs
