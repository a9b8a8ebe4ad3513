// Photo-consistency of a lattice point on a mesh face (paper section 2.3): the best
// of the 14 canonical orientations (orientations.h) of a 1 x mu line patch at X
// lying on the face plane (direction n_X x n_f), or, with Options::point_grid, of a
// mu x mu grid patch on the orientation's plane. The point is photo-consistent when
// score > Options::T. The stage loops over faces and lattice points and calls this.
#pragma once
#include <Eigen/Core>
#include <array>

#include "common/photo/orientations.h"
#include "common/photo/patch.h"

namespace tetmvs::photo {

struct PointResult : PatchResult {
  int orientation = -1;  // index into orientations(); -1 when no orientation had a score
  Eigen::Vector3d normal() const {
    return orientation >= 0 ? orientations()[orientation] : Eigen::Vector3d::Zero();
  }
  // True when the point is photo-consistent: defined and score > T.
  bool consistent(const Options& o) const { return valid() && score > o.T; }
};

// Best orientation at X on a face of normal nf (unit or not; nonzero; unused by grid
// patches), among the orientations whose bit is set in orientation_mask (bit o for
// orientations()[o]; all 14 by default). Ties between orientations go to the lower index. When per_orientation is given it receives each
// orientation's score (kNoScore where undefined).
PointResult score_point(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& nf,
                        const Options& opts, Scratch& scratch,
                        std::array<float, kNumOrientations>* per_orientation = nullptr,
                        std::uint16_t orientation_mask = kAllOrientations);

// The score of best's orientation (best: a valid result of score_point at X on a face of
// normal nf) at X moved t samples (best.spacing) along that orientation's normal, in best's
// views with best's number of partners; kNoScore when a view's patch leaves its image.
float score_offset(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& nf, const PointResult& best,
                   double t, const Options& opts, Scratch& scratch);

// Where the best orientation of `best` (a valid result of score_point at X on a face of
// normal nf) scores highest along its normal in the same views: the offset, in samples
// (best.spacing), among -steps..steps, refined by a parabola through the best sample and
// its neighbours; *peak_score receives the best sample's score. 0 (and best.score) when
// best is invalid or no offset scores higher.
double peak_offset(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& nf, const PointResult& best,
                   const Options& opts, Scratch& scratch, int steps, float* peak_score = nullptr);

// The views a point of Q is visible in: best's reference and the views among the kMaxK
// nearest to best's orientation (within the cone) whose patch at X agrees with the
// reference's (NCC above min_ncc; agreeing_views in patch.h), best first. Writes them to
// out (room for kMaxK) and returns their count (0 when best is invalid).
int visible_views(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& nf, const PointResult& best,
                  double min_ncc, const Options& opts, Scratch& scratch, int* out);

// score_point's patch of the one orientation o (0 .. kNumOrientations-1): its result as
// score_point would give it had o been the best.
PointResult score_orientation(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& nf, int o,
                              const Options& opts, Scratch& scratch);

// score_point for n points (X and nf: n x 3 row-major doubles), OpenMP-parallel with
// one Scratch per thread; out[i] does not depend on the thread count.
void score_points(const Views& views, const double* X, const double* nf, long n, const Options& opts,
                  PointResult* out);

}  // namespace tetmvs::photo
