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

// Best orientation at X on a face of normal nf (unit or not; nonzero). Ties between
// orientations go to the lower index. When per_orientation is given it receives each
// orientation's score (kNoScore where undefined).
PointResult score_point(const Views& views, const Eigen::Vector3d& X, const Eigen::Vector3d& nf,
                        const Options& opts, Scratch& scratch,
                        std::array<float, kNumOrientations>* per_orientation = nullptr);

// score_point for n points (X and nf: n x 3 row-major doubles), OpenMP-parallel with
// one Scratch per thread; out[i] does not depend on the thread count.
void score_points(const Views& views, const double* X, const double* nf, long n, const Options& opts,
                  PointResult* out);

}  // namespace tetmvs::photo
