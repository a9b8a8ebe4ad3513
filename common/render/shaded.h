// Pictures of meshes for people: shaded renders from the dataset's cameras, optionally
// over the photo, and silhouette agreement with the dataset's silhouettes.
#pragma once
#include <filesystem>
#include <opencv2/core.hpp>
#include <vector>

#include "common/scene.h"
#include "common/trimesh/trimesh.h"

namespace tetmvs {

// Headlight-shaded render (RGB, CV_8UC3) of a mesh from a camera; background black, or
// the photo dimmed when `photo` is given. Back faces are tinted red (wrong orientation
// shows at a glance).
cv::Mat render_shaded(const TriMesh& m, const Camera& cam, const cv::Mat* photo = nullptr);

// A row of shaded renders from `views` (default: four views spread over the scene).
cv::Mat render_sheet(const TriMesh& m, const Scene& s, std::vector<int> views = {}, int width = 320);

// Four views spread evenly over the cameras.
std::vector<int> spread_views(int num_cameras, int count = 4);

struct SilhouetteAgreement {
  std::vector<int> views;       // views with a silhouette
  std::vector<double> iou;      // per view
  std::vector<char> cut_by_border;  // per view: the true silhouette touches the image border
  double mean_iou = 0;
  double mean_iou_inside = -1;  // over the views whose silhouette lies inside the image (-1: none)
  double mean_boundary_px = 0;  // mean distance from the mesh silhouette's boundary to the true one
  double p95_boundary_px = 0;
};

// Compares the mesh's rendered silhouette with each valid silhouette of the scene, inside the
// image (the image border is not an outline: common/silhouette/border.h).
SilhouetteAgreement silhouette_agreement(const TriMesh& m, const Scene& s);

}  // namespace tetmvs
