// The photometric force of deform (paper section 3.3's texture force, as a variational
// multi-view refinement: Vu, Labatut, Pons, Keriven, PAMI 2012, written for this project).
//
// For each view i and each of its partners j, every pixel q of view i that the mesh covers
// gives the point X(q) where the ray of q meets the mesh; I_ij(q) = I_j(project_j(X(q))) is
// view j's image reprojected into view i through the mesh. The energy is the sum over
// windows (w x w pixels of view i) of 1 - NCC(I_i, I_ij). Its derivative with respect to
// I_ij(q) (box filters of the window statistics), times the gradient of view j's image
// along the projected ray of q, is its derivative with respect to the depth of X(q); moving
// vertex v along its normal by d moves the ray's hit point by b_v (n_f . n_v) / (n_f . r) d
// along the ray r (b_v: the barycentric weight of v in the face f that q sees). Summed over
// pixels and pairs this gives each vertex a gradient g_v and a Gauss-Newton curvature h_v,
// lumped (weighted by b_v, not b_v^2: a region that moves as one gets the exact
// Gauss-Newton step). The step of a vertex is -g / (h + damping) after g and h are averaged
// over a neighbourhood of about a pixel of the images used (photometric_steps).
//
// Pixels are used only where the image value belongs to the mesh point alone: a pixel of
// view i (or its projection in view j) within kCleanPx pixels of an occluding contour or
// of the background is left out (the images there mix two surfaces, and the mix biases the
// depth inward, by a tenth of a pixel of the level's scale on the synthetic torus), as are
// points hidden in view j (z-buffer) and faces seen grazing in either view.
//
// Results do not depend on the thread count: views are processed in a fixed number of
// slots, each in view order, and the slots are summed in order.
#pragma once
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <cstdint>
#include <vector>

#include "common/camera.h"
#include "common/deform/topology.h"
#include "common/photo/views.h"
#include "common/trimesh/raster.h"

namespace tetmvs::deform {

struct PhotometricGradient {
  std::vector<double> grad;    // dE / dd_v per vertex (d: offset along the vertex normal, world units)
  std::vector<double> hess;    // lumped Gauss-Newton curvature per vertex (0: no pixel)
  std::vector<double> pairs;   // the pixel pairs behind hess, weighted as in it but not by the match
  std::int64_t pixels = 0;     // pixel pairs used
  double mean_ncc = 0;         // mean NCC over the windows used
};

// One image-pyramid level of the photometric force: the views' images reduced `level`
// times (photo::Views::reduced), their cameras (reduced_cameras) and image gradients
// (central differences, CV_32F), made once per level.
struct PhotoLevel {
  int level = 0;
  photo::Views views;
  std::vector<Camera> cams;
  std::vector<cv::Mat> gx, gy;
};
PhotoLevel make_photo_level(const photo::Views& full, const std::vector<Camera>& cams, int level);

// partners[i]: the views compared with view i. N: unit vertex normals. window: odd, >= 3.
// rasters: the mesh rasterised in every view of this level with back faces culled, when
// the caller has them (deform's own rasters, subsampled at the reduced levels); empty:
// rasterised here.
PhotometricGradient photometric_gradient(const std::vector<Eigen::Vector3d>& V, const std::vector<Eigen::Vector3i>& F,
                                         const std::vector<Eigen::Vector3d>& N, const PhotoLevel& lv,
                                         const std::vector<std::vector<int>>& partners, int window,
                                         const std::vector<const Raster*>& rasters = {});

// Per vertex, the step along its normal (world units) toward the minimum of the energy:
// g, h and the pairs n averaged over 2 x 2^(level - mesh_level) 1-rings (about a pixel of the
// level's images on a mesh of ~3 px edges measured at pyramid level mesh_level), step =
// -g / (h + damping + floor), clamped to 2 pixels of the level's images (fp: each vertex's
// full-resolution pixel footprint). On the reduced images (level >= 1) damping =
// 0.2 median(h / n) n, per pixel pair: a vertex that few views see is damped as little, for
// its windows, as one that many see. On the full images (level 0) damping = 0.1 median(h) and
// floor = noise_floor n / fp^2, an absolute damping: a vertex whose windows match with less
// image gradient than that (plaster, weak texture: the step would follow the noise) moves
// little, while the relative damping alone leaves every step as long where all windows are
// weak. 0 where no pixel sees it.
std::vector<double> photometric_steps(const PhotometricGradient& g, const Topology& topo, int level, int mesh_level,
                                      const std::vector<double>& fp, double noise_floor = 0);

// Partners of each view: the views whose direction from `centre` lies min_deg..max_deg
// from the view's, nearest first, at most `count`.
std::vector<std::vector<int>> photometric_partners(const std::vector<Camera>& cams, const Eigen::Vector3d& centre,
                                                   double min_deg, double max_deg, int count);

// The cameras of image-pyramid level `level` (photo::Views::reduced): pixel (u, v) of the
// reduced image is pixel (2^level u, 2^level v) of the original; sizes as cv::pyrDown's.
std::vector<Camera> reduced_cameras(const std::vector<Camera>& cams, int level);

}  // namespace tetmvs::deform
