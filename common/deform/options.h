// Options of deform (paper section 3.3), validated up front by check(). Defaults,
// units and meanings: params/defaults.json ("deform.*") and docs/deform.md.
#pragma once
#include <cstdint>

namespace tetmvs {
class Params;

namespace deform {

struct Options {
  int iterations = 12;            // deformation iterations
  // smoothness (non-shrinking): tangential umbrella + small normal umbrella + normal bi-Laplacian
  double smooth_tangent = 0.5;    // weight of the umbrella's tangential component (mesh relaxation)
  double smooth_normal = 0.05;    // weight of the umbrella's normal component (shrinks: keep small)
  double smooth_bilaplacian = 0.4;  // weight of the bi-Laplacian's normal component (does not shrink spheres); < 0.5
  // silhouette force
  double w_silhouette = 0.5;      // fraction of the silhouette correction applied per iteration
  double rim_cos = 0.5;           // a vertex can be on a view's rim when |n . ray| < rim_cos
  double sil_band_px = 1.5;       // ... and its pixel is within this distance of the rendered mesh's background
  double sil_max_px = 5.0;        // largest silhouette correction per view (pixels)
  double visibility_tol_px = 3.0; // a vertex is visible when not behind the z-buffer by more than this (pixels)
  // texture force
  double w_texture = 0.5;         // fraction of the texture correction applied per iteration
  double texture_range_px = 5.0;  // offsets along the normal: -range..+range pixels
  double texture_far_px = 15.0;   // ... and -far..far when that shows no clear peak (= range: never)
  double texture_far_min_score = 0.9;  // ... where the peak must reach this score
  double texture_far_min_contrast = 0.1;  // ... and exceed the lowest score on each side by this
  double texture_coarse_px = 1.0; // ... first every this many pixels
  double texture_step_px = 0.5;   // ... refined down to steps of this (then a parabola)
  double texture_min_score = 0.5; // the peak score must reach this
  double texture_min_contrast = 0.03;  // ... and exceed the profile's minimum by this
  double texture_cone_deg = 75;   // camera cone of the texture patches (replaces photo.cone_deg there)
  int texture_mu = 11;            // patch size in samples (one reference pixel apart)
  int texture_partners = 4;       // views compared with the reference
  int texture_min_partners = 2;   // fewest partners for a score
  double texture_baseline_min_deg = 10;  // a partner's direction is at least this far from the reference's
  double texture_baseline_max_deg = 40;  // ... and at most this far
  double texture_settle_px = 0.25;  // a vertex whose peak is nearer than this has settled: probed again only ...
  int texture_recheck = 3;        // ... every this many texture iterations (1: every vertex every iteration)
  int texture_sag_rounds = 8;     // offsets corrected for the surface's sag under the plane patch, curvature
                                  // smoothed over this many 1-rings (0: no correction)
  double texture_ring_weight = 0.5; // the texture move blends the 1-ring's applied offsets with this weight
  int texture_start = 2;          // first iteration with the texture force (smooth the lattice facets first)
  int texture_pyramid = 1;        // the texture force starts on this image-pyramid level (texture_level)
  bool occlusion = true;          // drop views in which the vertex is occluded from its patches
  // step control and remeshing
  double max_move_px = 1.0;       // largest move of a vertex per iteration (pixels)
  double max_edge_px = 3.0;       // split edges longer than this in their finest view
  double min_edge_px = 1.35;      // collapse edges shorter than this (below max_edge_px / 2)
  double needle_ratio = 0.2;      // collapse the shortest edge of triangles with shortest/longest below this
  double flip_dihedral_deg = 30;  // Delaunay flips only between triangles within this angle of coplanar
  int intersection_retries = 4;   // halve the step of the vertices of new intersections this often, then revert them

  void check() const;  // throws tetmvs::Error naming the bad value
  static Options from_params(const Params& p);  // reads deform.*, then check()s
  // The image-pyramid level of the texture force at iteration `it`: the first third of
  // the texture iterations shared by levels texture_pyramid .. 1, coarsest first, the rest
  // on the full images (always 0 when texture_pyramid is 0).
  int texture_level(int it) const;
};

}  // namespace deform
}  // namespace tetmvs
