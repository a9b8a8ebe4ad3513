// A synthetic scene as a COLMAP workspace: the same cameras, images and (optionally)
// silhouettes as the Middlebury-layout folder that `synth` writes, with a sparse model
// whose points3D are ground-truth surface points and whose 2-D observations are their
// exact projections in the views that see them (not occluded, inside the image).
//
//   <out>/images/<name>          the rendered images (copied)
//   <out>/sparse/cameras.txt     PINHOLE cameras (one per distinct K), COLMAP pixel convention
//   <out>/sparse/images.txt      poses (quaternion, translation) and observations
//   <out>/sparse/points3D.txt    the surface points and their tracks
//   <out>/silhouettes/<name>     the masks (unless silhouettes = false)
//   <out>/gt.ply                 the ground truth (so pipeline.mk evaluates the run)
// No bbox.txt: ingest finds the box from the silhouettes or the sparse points.
#pragma once
#include <cstdint>
#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "common/camera.h"
#include "common/ingest/colmap.h"
#include "common/trimesh/trimesh.h"

namespace tetmvs::synth {

struct ColmapExportOptions {
  int points = 2000;         // surface samples drawn (those seen by < 2 views are dropped)
  std::uint64_t seed = 1;
  bool silhouettes = true;   // copy silhouettes/
  bool binary = false;       // write the .bin files instead of the .txt ones
};

// The COLMAP model of `cams` (pinhole, zero skew) observing the surface samples of `gt`.
// rgb (optional, one per camera) gives the points' colours. Image ids are 1..N in camera
// order; point ids 1..M.
colmap::Model colmap_model(const std::vector<Camera>& cams, const TriMesh& gt, const std::vector<cv::Mat>* rgb,
                           int points, std::uint64_t seed);

// Exports the synthetic dataset folder `dataset` (as written by synth) to the workspace
// `out`. Returns a summary {images, cameras, points, observations}.
nlohmann::json export_colmap(const std::filesystem::path& dataset, const std::filesystem::path& out,
                             const ColmapExportOptions& o);

}  // namespace tetmvs::synth
