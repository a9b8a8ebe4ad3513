// Silhouette-fix (paper section 3.2, Fig. 5): the first cut's surface S1 is rendered into
// every view with a silhouette and compared with the true silhouette; the disagreements
// become new hard labels (constraints) for a second cut.
//
//  S1 TOO BIG (pixel inside S1's silhouette, outside the true one, at least `margin_px`
//  from the true silhouette's boundary): the ray from the camera centre through the pixel
//  centre is walked through the mesh (tet::walk_ray) and every cell on it that is provably
//  outside the object becomes EXTERIOR. "Provably": the cell's whole projection in this
//  view (the convex hull of its four projected corners, grown by `pad_px`) lies inside the
//  image and covers no true-silhouette pixel. A cell on such a ray that straddles the
//  silhouette in this view is left free (counted as `straddling`): labelling it would
//  force the cut inside the object.
//
//  S1 TOO SMALL (pixel inside the true silhouette, at least `margin_px` from its boundary,
//  outside S1's silhouette): connected regions of such pixels (8-connected) are sampled in
//  farthest-point order (first the pixel deepest inside the true silhouette, then each time
//  the pixel farthest from all tried ones, so that a few samples cover a horn's base and
//  tip alike), until `max_per_region` of them gave a constraint, every pixel of the region
//  is within `spacing_px` of a tried one, or 20 x max_per_region rays were tried. For each
//  sampled pixel the ray is walked;
//  cells outside the visual hull (reasons kBoundary and kOutsideHull, or a centroid outside a
//  silhouette) are dropped. When the rest is ONE contiguous run of cells (a single
//  segment), the faces crossed in it are scored: front-facing omega (the orientation whose
//  normal points toward the camera) and back-facing omega (the other one). The strongest
//  front-facing face F (nearest on ties) must reach `min_peak`; behind it the strongest
//  back-facing score B must reach `min_peak`; the first face behind F whose back-facing
//  score is >= `peak_ratio` * B closes the depth interval. The cell holding the interval's
//  middle becomes INTERIOR, provided its four corners project inside every silhouette.
//  Rays with no segment or several, weak peaks, or a failed corner check are skipped and
//  counted. Two options (off by default: the paper's rule) serve surfaces that lie in a thin
//  band under the visual hull, as with the hull-core prior, where S1 misses a band of 1-4 px
//  all along the rim: `max_gap_cells` joins runs separated by at most that many cells outside
//  the hull into one segment (a ray grazing the hull crosses its jagged cell boundary several
//  times: 78 % of dinoRing's rays had several segments), and `search_interval` takes, when
//  the middle cell fails the corner check, the nearest cell of the interval that passes it.
//
//  Hard labels are never overturned: an exterior constraint on an interior cell, or an
//  interior constraint on an exterior cell (from label or from this pass), is a conflict:
//  skipped and counted. Exterior constraints are applied first (they only rest on the
//  silhouettes). The result is deterministic whatever the thread count (views are
//  processed in parallel and merged in view order).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "common/param_binding.h"
#include "common/reason.h"
#include "common/scene.h"
#include "common/tetmesh/locate.h"
#include "common/tetmesh/tetmesh.h"
#include "common/trimesh/trimesh.h"

namespace tetmvs {
class Params;
}

namespace tetmvs::silfix {

struct Options {
  double margin_px = 2.0;    // error pixels must be at least this far from the true boundary
  double pad_px = 1.0;       // exterior: the cell's projection grown by this must miss the silhouette
  int max_per_region = 5;    // interior constraints per view and connected error region
  double spacing_px = 3.0;   // sampling of a region stops when all its pixels are this close to tried ones
  int min_region_px = 4;     // error regions with fewer pixels are ignored
  double min_peak = 0.5;     // front and back peaks must reach this omega
  double peak_ratio = 0.8;   // "next significant back-facing peak": >= this * the strongest behind
  bool search_interval = false;  // when the middle cell fails the corner test, try the others in the interval
  int max_gap_cells = 0;     // runs of inside cells separated by at most this many outside cells are one segment
  bool exterior = true;      // add exterior constraints
  bool interior = true;      // add interior constraints
  void check() const;        // throws Error on a value outside its documented range
  static Options from_params(const Params& p);  // reads silfix.*, then check()s

  static constexpr auto params() {  // the fields that hold parameters (common/param_binding.h)
    return std::to_array<ParamField<Options>>({
        {"silfix.margin_px", &Options::margin_px},
        {"silfix.pad_px", &Options::pad_px},
        {"silfix.max_per_region", &Options::max_per_region},
        {"silfix.spacing_px", &Options::spacing_px},
        {"silfix.min_region_px", &Options::min_region_px},
        {"silfix.min_peak", &Options::min_peak},
        {"silfix.peak_ratio", &Options::peak_ratio},
        {"silfix.search_interval", &Options::search_interval},
        {"silfix.max_gap_cells", &Options::max_gap_cells},
    });
  }
};

enum Kind : std::int8_t { kExteriorKind = -1, kInteriorKind = 1 };
// Why a constraint was added (the /constraints/why codes of silfix.h5).
enum Why : std::uint8_t {
  kWhyOutsideSilhouette = 1,  // exterior: on the ray of a too-big pixel, projection clear of the silhouette
  kWhyPeakInterval = 2,       // interior: centre of the front/back photo-consistency peak interval
};

struct Constraint {
  std::int32_t view = 0, u = 0, v = 0;  // the pixel whose ray gave it
  std::int32_t cell = 0;
  std::int8_t kind = 0;       // Kind
  std::uint8_t why = 0;       // Why
  float omega_front = 0, omega_back = 0;  // interior: the two peaks (0 for exterior)
  float depth_front = 0, depth_back = 0;  // interior: their distances from the camera centre
                                          // along the ray (world units; 0 for exterior)
};

struct ViewStats {
  std::int32_t view = 0;
  double iou = 0;                           // S1's silhouette vs the true one
  std::int64_t s1_px = 0, true_px = 0;      // pixels inside each silhouette
  std::int64_t too_big_px = 0, too_small_px = 0;  // error pixels beyond the margin
  std::int64_t small_regions = 0;           // connected too-small regions (>= min_region_px)
  std::int64_t exterior_rays = 0, interior_rays = 0;
  std::int64_t straddling = 0;              // free cells on too-big rays not provably outside
  std::int64_t no_segment = 0, multi_segment = 0, weak_peaks = 0, corner_outside = 0;
  std::int64_t exterior_added = 0, interior_added = 0;  // after the merge
  std::int64_t conflicts = 0, already = 0;              // after the merge
};

struct Result {
  std::vector<std::int8_t> label;     // updated labels (1 interior, -1 exterior, 0 free)
  std::vector<std::uint8_t> reason;   // updated reasons (kSilfixExterior, kSilfixInterior for the new ones)
  std::vector<Constraint> constraints;  // added, in merge order (exterior first, by view)
  std::vector<ViewStats> views;       // one per view with a silhouette
  std::vector<cv::Mat> s1_masks;      // per camera: S1's silhouette (CV_8U 255), empty without silhouette
  std::int64_t exterior_added = 0, interior_added = 0, conflicts = 0, already = 0;
  double mean_iou = 0;                // mean over views with a silhouette
};

// S1's silhouette in a view: 255 where the pixel centre sees the surface (exact rasteriser).
cv::Mat surface_mask(const TriMesh& surface, const Camera& cam);

// True when the projection of points X (the convex hull of their images, grown by pad_px)
// lies inside the image and contains no non-zero pixel of `mask`. All points must be in
// front of the camera (false otherwise).
bool projection_clear_of_mask(const Camera& cam, const cv::Mat& mask, const Eigen::Vector3d* X, int n,
                              double pad_px);

// The analysis of one too-small ray (exposed for tests). hits: the walk from the camera
// centre; outside[i]: hit i is outside the visual hull. Returns the index into hits of the
// interior cell, or -1 with `status` saying why: 1 no segment, 2 several, 3 weak peaks.
struct RayPeaks {
  int status = 0;
  float omega_front = 0, omega_back = 0;
  double t_front = 0, t_back = 0;
};
int interior_hit_on_ray(const tet::TetMesh& m, const std::vector<float>& omega,
                        const std::vector<tet::WalkHit>& hits, const std::vector<std::uint8_t>& outside,
                        const Options& o, RayPeaks& peaks);

// The whole pass. omega: 2 per face (graph_cut.h); label/reason: from label (labels.h5);
// s1: the first cut's surface (cut::cut_surface of /cells/inside, or cut1.ply).
Result fix_silhouettes(const tet::TetMesh& m, const Scene& s, const TriMesh& s1, const std::vector<float>& omega,
                       const std::vector<std::int8_t>& label, const std::vector<std::uint8_t>& reason,
                       const Options& o);

// ---- pictures (pictures.cpp) ----
// One view: green = both silhouettes, red = S1 only (S1 too big), blue = true only (S1 too
// small); pixels within the margin of the true boundary in darker shades; exterior
// constraint pixels marked by magenta dots, interior ones by yellow crosses.
cv::Mat view_picture(const cv::Mat& truth, const cv::Mat& s1, const std::vector<Constraint>& constraints,
                     int view, double margin_px);
// All views' pictures tiled (tile width `tile_width`), each labelled with its view and IoU.
cv::Mat contact_sheet(const std::vector<cv::Mat>& pictures, const std::vector<std::string>& captions,
                      int tile_width = 240);

}  // namespace tetmvs::silfix
