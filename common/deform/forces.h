// The three forces of deform (paper section 3.3), each a per-vertex displacement
// (world units) computed from the current positions only, independently per vertex
// (OpenMP over vertices; results do not depend on the thread count):
//   smoothness  tangential umbrella + small normal umbrella + normal bi-Laplacian;
//   silhouette  rim vertices of a view moved across the view ray so that their
//               projection lands on the true silhouette's boundary (signed distance map);
//   texture     the best photo-consistency offset along the vertex normal.
#pragma once
#include <Eigen/Dense>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "common/camera.h"
#include "common/deform/options.h"
#include "common/deform/topology.h"
#include "common/photo/options.h"
#include "common/photo/views.h"
#include "common/trimesh/trimesh.h"

namespace tetmvs::deform {

// Signed distance (pixels) to the boundary of a silhouette mask (255 = object), positive
// outside, negative inside, zero half-way between an object pixel centre and a background
// pixel centre. CV_32F.
cv::Mat signed_distance(const cv::Mat& mask);

// Per-view state of one iteration: the current mesh rasterised into the view.
struct ViewRaster {
  cv::Mat depth;   // CV_32F camera z, +inf where empty
  cv::Mat sd;      // CV_32F signed distance (px) to the boundary of the mesh's own silhouette (signed_distance)
  std::int64_t covered = 0, agree = 0, either = 0;  // silhouette IoU counts (views with silhouettes)
};
// sil: the view's silhouette (empty: no IoU counts).
ViewRaster rasterize_view(const TriMesh& mesh, const Camera& cam, const cv::Mat& sil);

// Area-weighted unit vertex normals.
std::vector<Eigen::Vector3d> vertex_normals(const std::vector<Eigen::Vector3d>& V,
                                            const std::vector<Eigen::Vector3i>& F);

// Mean curvature H per vertex (1/length; > 0 where convex, for outward normals): the mean
// over the 1-ring of the normal curvatures (n_j - n_v) . (x_j - x_v) / |x_j - x_v|^2, then
// averaged over the 1-ring `rounds` times (the estimate is noisy on a rough mesh).
std::vector<double> mean_curvature(const std::vector<Eigen::Vector3d>& V, const std::vector<Eigen::Vector3d>& N,
                                   const Topology& topo, int rounds);

// Pixel footprint (depth / focal) of each vertex in its finest view among those where it
// is in front and inside the image; `fallback` where no view sees it.
std::vector<double> vertex_footprints(const std::vector<Eigen::Vector3d>& V, const std::vector<Camera>& cams,
                                      double fallback);

// vis[v * nviews + i] = 1 when vertex v is in front of view i, inside its image and not
// behind the view's z-buffer by more than tol_px pixel footprints.
std::vector<std::uint8_t> vertex_visibility(const std::vector<Eigen::Vector3d>& V, const std::vector<Camera>& cams,
                                            const std::vector<ViewRaster>& rasters, double tol_px);

// Smoothness displacement per vertex.
std::vector<Eigen::Vector3d> smooth_force(const std::vector<Eigen::Vector3d>& V, const Topology& topo,
                                          const std::vector<Eigen::Vector3d>& N, const Options& opt);

// Silhouette displacement per vertex (mean over the views where the vertex is on the
// rim: visible, |n . ray| < rim_cos, within sil_band_px inside the mesh's own rendered
// silhouette). In a view, the vertex moves across the ray (along n minus its ray
// component) so that the mesh's contour near it lands on the true one: by
// (sd_true - sd_mesh) / slope, clamped to sil_max_px. rim_views[v] receives the number
// of such views. sd: signed_distance of each view's
// silhouette (empty Mat: no silhouette, no force).
std::vector<Eigen::Vector3d> silhouette_force(const std::vector<Eigen::Vector3d>& V,
                                              const std::vector<Eigen::Vector3d>& N, const std::vector<double>& fp,
                                              const std::vector<Camera>& cams, const std::vector<cv::Mat>& sd,
                                              const std::vector<ViewRaster>& rasters,
                                              const std::vector<std::uint8_t>& vis, const Options& opt,
                                              std::vector<int>& rim_views);

struct TextureProbe {
  float best_score = -1.f;  // best score along the normal (-1: no score anywhere)
  float offset_px = 0.f;    // refined offset of the peak (pixels along the normal)
  bool applied = false;     // the peak was clear: the force moves toward it
  bool probed = false;      // the vertex was active (its profile was measured)
  bool far = false;         // no clear peak within texture_range_px: searched to texture_far_px
};

// Texture displacement per vertex (a plane sweep along the normal). Views: among those
// that see the vertex (vis; may be empty: all) within texture_cone_deg of its normal, the
// reference is the most frontal one; its partners are the next most frontal views whose
// direction lies texture_baseline_min_deg..max_deg from the reference's (wide enough for
// depth to show, at most texture_partners of them). A texture_mu x texture_mu patch on
// the plane through X + t n (sample spacing: one reference pixel) is sampled in each;
// the score at t is the mean NCC of the reference with its partners. t runs over
// -range..range pixels (of the vertex's finest view) every texture_coarse_px, and over
// -far..far (texture_far_px) when that shows no clear peak; around the best, steps halve
// down to texture_step_px, then a parabola through the peak and its neighbours. When the peak is clear (score >= texture_min_score and the coarse profile
// drops by texture_min_contrast on both sides) the displacement is offset * n.
// active (may be empty: all): vertices to probe; the others get no force and an empty probe.
// curvature (may be empty: none): mean curvature H per vertex (mean_curvature). The patch is
// planar but the surface curves away from it: the plane that matches a convex patch best
// lies inside the surface by the patch's mean sag, H * mean((i - c)^2) * spacing^2 (0.14
// px on the synthetic torus' outside, measured); the offset is corrected by it.
// views may be an image-pyramid level of the scene's (photo::Views::reduced): px_scale is
// then its pixel size in full-resolution pixels (2^level), and the offsets, ranges and
// steps above are in its pixels (fp stays the full resolution's footprint).
std::vector<Eigen::Vector3d> texture_force(const std::vector<Eigen::Vector3d>& V,
                                           const std::vector<Eigen::Vector3d>& N, const std::vector<double>& fp,
                                           const photo::Views& views, const std::vector<std::uint8_t>& vis,
                                           const std::vector<std::uint8_t>& active, const Options& opt,
                                           const photo::Options& popt, std::vector<TextureProbe>& probes,
                                           const std::vector<double>& curvature = {}, double px_scale = 1.0);

}  // namespace tetmvs::deform
