// The three forces of deform (paper section 3.3), each a per-vertex displacement
// (world units) computed from the current positions only, independently per vertex
// (OpenMP over vertices; results do not depend on the thread count):
//   smoothness  tangential umbrella + small normal umbrella + normal bi-Laplacian;
//   silhouette  rim vertices of a view moved across the view ray so that their
//               projection lands on the true silhouette's boundary (signed distance map);
//   photometric the Gauss-Newton step of a multi-view image similarity (photometric.h).
#pragma once
#include <Eigen/Dense>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "common/camera.h"
#include "common/deform/options.h"
#include "common/deform/topology.h"
#include "common/trimesh/raster.h"
#include "common/trimesh/trimesh.h"

namespace tetmvs::deform {

// Signed distance (pixels) to the boundary of a silhouette mask (255 = object), positive
// outside, negative inside, zero half-way between an object pixel centre and a background
// pixel centre. CV_32F.
cv::Mat signed_distance(const cv::Mat& mask);

// signed_distance of a CV_8U mask (non-zero = object) where the distance is at most `reach`
// pixels, +-(reach + 0.5) beyond (the side's sign); up to a reach of 16 px the cost is the
// outline's length times the reach's disc, not the image's size.
cv::Mat signed_distance_near(const cv::Mat& obj, int reach);

// Per-view state of one iteration: the current mesh rasterised into the view.
struct ViewRaster {
  Raster raster;   // back faces culled (depth and triangle ids)
  cv::Mat depth;   // CV_32F camera z, +inf where empty (raster.depth)
  cv::Mat sd;      // CV_32F signed distance (px) to the boundary of the mesh's own silhouette (signed_distance_near)
  std::int64_t covered = 0, agree = 0, either = 0;  // silhouette IoU counts (views with silhouettes)
};
// sil: the view's silhouette (empty: no IoU counts). sd_reach: the distance within which sd is
// exact (sd_reach_px of the options the silhouette force uses).
ViewRaster rasterize_view(const TriMesh& mesh, const Camera& cam, const cv::Mat& sil, int sd_reach);

// Area-weighted unit vertex normals.
std::vector<Eigen::Vector3d> vertex_normals(const std::vector<Eigen::Vector3d>& V,
                                            const std::vector<Eigen::Vector3i>& F);

// Pixel footprint (depth / focal) of each vertex in its finest view among those where it
// is in front and inside the image; `fallback` where no view sees it.
std::vector<double> vertex_footprints(const std::vector<Eigen::Vector3d>& V, const std::vector<Camera>& cams,
                                      double fallback);

// vis[v * nviews + i] = 1 when vertex v is in front of view i, inside its image and not
// behind the view's z-buffer by more than tol_px pixel footprints.
std::vector<std::uint8_t> vertex_visibility(const std::vector<Eigen::Vector3d>& V, const std::vector<Camera>& cams,
                                            const std::vector<ViewRaster>& rasters, double tol_px);

// Smoothness displacement per vertex: smooth_tangent x the umbrella's tangential part +
// smooth_normal x its normal part, and along the normal either - smooth_bilaplacian x the
// bi-Laplacian's normal part or, on the full images (fairing = true, smooth_fairing > 0), the
// curvature fairing: smooth_fairing x (the umbrella's normal part minus that part's mean
// over kFairingRounds rounds of one-ring averaging, about 10 pixels on the full images' mesh
// of ~3-px edges). The fairing evens out the mean curvature at the scale of a few vertices
// (the jitter that whole photometric steps leave on weak texture) and leaves a sphere's or a
// cylinder's alone, where the umbrella's normal part (mean-curvature flow) shrinks them.
constexpr int kFairingRounds = 12;
std::vector<Eigen::Vector3d> smooth_force(const std::vector<Eigen::Vector3d>& V, const Topology& topo,
                                          const std::vector<Eigen::Vector3d>& N, const Options& opt,
                                          bool fairing = false);

// Silhouette displacement per vertex (mean over the views where the vertex is on the
// rim: visible (as vertex_visibility with opt.visibility_tol_px), |n . ray| < rim_cos, within sil_band_px inside the mesh's own rendered
// silhouette). In a view, the vertex moves across the ray (along n minus its ray
// component) so that the mesh's contour near it lands on the true one: by
// (sd_true - sd_mesh) / slope, less sil_tolerance_px, clamped to sil_max_px. rim_views[v] receives the number
// of such views. sd: signed_distance of each view's
// silhouette (empty Mat: no silhouette, no force).
std::vector<Eigen::Vector3d> silhouette_force(const std::vector<Eigen::Vector3d>& V,
                                              const std::vector<Eigen::Vector3d>& N, const std::vector<double>& fp,
                                              const std::vector<Camera>& cams, const std::vector<cv::Mat>& sd,
                                              const std::vector<ViewRaster>& rasters, const Options& opt,
                                              std::vector<int>& rim_views);

// The silhouette force's reach around the rim. Without it a rim vertex pulled out moves
// alone and raises a fin along its contour generator, leaving a fold where the true surface
// continues between the contours of two groups of views (the top of a torus seen by a ring
// of cameras). A vertex without a correction of its own within reach_px (pixels of the
// images the mesh follows: footprint fp times level_scale) of vertices pulled outward, along
// the mesh's edges, moves along its normal by their corrections' mean normal part times
// 1 - distance / reach_px. Corrections of max_source_px (full-resolution pixels) or more do
// not spread: they mark a part missing from the mesh (a cup's rim the cut took off), which
// its rim vertices bring back by themselves, and the surface around them (the lid over the
// cup's cavity) must not follow. Returns the step along N per vertex (0 for the corrected
// vertices and those out of reach).
struct SpreadOptions {
  double reach_px = 0;        // 0: no spread
  double level_scale = 1;     // 2^mesh_level
  double max_source_px = 0;
};
std::vector<double> silhouette_spread(const std::vector<Eigen::Vector3d>& V, const std::vector<Eigen::Vector3d>& N,
                                      const std::vector<double>& fp, const Topology& topo,
                                      const std::vector<Eigen::Vector3d>& fsil, const SpreadOptions& o);

}  // namespace tetmvs::deform
