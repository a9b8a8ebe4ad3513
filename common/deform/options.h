// Options of deform (paper section 3.3), validated up front by check(). Defaults,
// units, ranges and meanings: params/defaults.json ("deform.*", bound in params()) and
// docs/deform.md.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>

#include "common/param_binding.h"

namespace tetmvs {
class Params;

namespace deform {

struct Options {
  int iterations = 34;            // deformation iterations
  // smoothness (non-shrinking): tangential umbrella + small normal umbrella + normal bi-Laplacian
  double smooth_tangent = 0.5;    // weight of the umbrella's tangential component (mesh relaxation)
  double smooth_normal = 0.05;    // weight of the umbrella's normal component (shrinks: keep small)
  double smooth_bilaplacian = 0.4;  // weight of the bi-Laplacian's normal component (does not shrink spheres); < 0.5
  double smooth_fairing = 1.2;    // on the full images, instead of the bi-Laplacian: weight of the curvature fairing
  // silhouette force
  double w_silhouette = 1.0;      // fraction of the silhouette correction applied per iteration
  double rim_cos = 0.5;           // a vertex can be on a view's rim when |n . ray| < rim_cos
  double sil_band_px = 1.5;       // ... and its pixel is within this distance of the rendered mesh's background
  double sil_max_px = 5.0;        // largest silhouette correction per view (pixels)
  double visibility_tol_px = 3.0; // a vertex is visible when not behind the z-buffer by more than this (pixels)
  double sil_tolerance_px = 0.5;  // silhouette disagreements up to this are left to the photometric force
  double sil_spread_px = 3;       // a correction also moves the vertices this far around it (pixels of mesh_level; 0: off)
  // photometric force (photometric.h)
  double w_photo = 0.5;           // fraction of the photometric step applied per iteration on the reduced images
  int photo_start = 2;            // first iteration with the photometric force (smooth the lattice facets first)
  int photo_window = 7;           // NCC window side, pixels of the images in use (odd)
  int photo_partners = 4;         // views reprojected into each view and compared with it ...
  double photo_baseline_min_deg = 10;  // ... whose direction lies at least this far from the view's
  double photo_baseline_max_deg = 40;  // ... and at most this far
  int photo_coarsest_level = 4;   // the force starts on the images reduced this many times ...
  int photo_level_iterations = 7; // ... spending this many iterations on each reduced level
  double photo_noise_floor = 0.003;  // full images: curvature floor per pixel pair (normalised gradient^2 per pixel^2)
  double photo_momentum = 0.7;    // reduced images: this share of the last photometric step, smoothed, joins the next
  // step control and remeshing
  double max_move_px = 3.0;       // largest move of a vertex per iteration (full-resolution pixels, finest view)
  double max_edge_px = 3.0;       // split edges longer than this in their finest view (pixels of mesh_level)
  double min_edge_px = 1.35;      // collapse edges shorter than this (below max_edge_px / 2)
  double needle_ratio = 0.2;      // collapse the shortest edge of triangles with shortest/longest below this
  double flip_dihedral_deg = 30;  // Delaunay flips only between triangles within this angle of coplanar
  int intersection_retries = 4;   // halve the step of the vertices of new intersections this often, then revert them

  // Throws tetmvs::Error naming the bad value: the documented ranges, then max_edge_px >
  // 2 min_edge_px, an odd photo_window, photo_baseline_min_deg <= photo_baseline_max_deg.
  void check() const;
  static Options from_params(const Params& p);  // reads deform.*, then check()s
  // The image-pyramid level of the photometric force at iteration `it` (-1: no photometric
  // force yet): photo_level_iterations iterations on each of the levels photo_coarsest_level
  // .. 1, then the full images (0).
  int photo_level(int it) const;
  // The image-pyramid level in whose pixels max_edge_px and min_edge_px are measured at
  // iteration `it`: the mesh follows the images in use (photo_level), at the coarsest level
  // before the photometric force starts and at the full images after the last iteration.
  int mesh_level(int it) const;
  // The distance (pixels) from the mesh's own silhouette within which the silhouette force
  // reads it: the rim band inside, a correction's reach outside.
  int sd_reach_px() const { return static_cast<int>(std::ceil(sil_band_px + sil_max_px)) + 1; }

  static constexpr auto params() {
    return std::to_array<ParamField<Options>>({
        {"deform.iterations", &Options::iterations},
        {"deform.smooth_tangent", &Options::smooth_tangent},
        {"deform.smooth_normal", &Options::smooth_normal},
        {"deform.smooth_bilaplacian", &Options::smooth_bilaplacian},
        {"deform.smooth_fairing", &Options::smooth_fairing},
        {"deform.w_silhouette", &Options::w_silhouette},
        {"deform.rim_cos", &Options::rim_cos},
        {"deform.sil_band_px", &Options::sil_band_px},
        {"deform.sil_max_px", &Options::sil_max_px},
        {"deform.visibility_tol_px", &Options::visibility_tol_px},
        {"deform.sil_tolerance_px", &Options::sil_tolerance_px},
        {"deform.sil_spread_px", &Options::sil_spread_px},
        {"deform.w_photo", &Options::w_photo},
        {"deform.photo_start", &Options::photo_start},
        {"deform.photo_window", &Options::photo_window},
        {"deform.photo_partners", &Options::photo_partners},
        {"deform.photo_baseline_min_deg", &Options::photo_baseline_min_deg},
        {"deform.photo_baseline_max_deg", &Options::photo_baseline_max_deg},
        {"deform.photo_coarsest_level", &Options::photo_coarsest_level},
        {"deform.photo_level_iterations", &Options::photo_level_iterations},
        {"deform.photo_noise_floor", &Options::photo_noise_floor},
        {"deform.photo_momentum", &Options::photo_momentum},
        {"deform.max_move_px", &Options::max_move_px},
        {"deform.max_edge_px", &Options::max_edge_px},
        {"deform.min_edge_px", &Options::min_edge_px},
        {"deform.needle_ratio", &Options::needle_ratio},
        {"deform.flip_dihedral_deg", &Options::flip_dihedral_deg},
        {"deform.intersection_retries", &Options::intersection_retries},
    });
  }
};

}  // namespace deform
}  // namespace tetmvs
