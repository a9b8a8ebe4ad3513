// Camera selection of the photo-consistency measure (paper section 2.3): the views
// whose direction from a 3-D point X to the camera centre is within the cone
// (Options::cone_deg) of a patch normal n, in which X is in front of the camera and
// projects inside the image (and inside the view's silhouette when
// Options::use_silhouettes and the view has one). Ordered by angle (smallest
// first), ties by view index. The measure takes the first k of these whose whole
// patch projects inside the image.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "common/photo/options.h"
#include "common/photo/scratch.h"
#include "common/photo/views.h"

namespace tetmvs::photo {

// All candidate views for (X, n), best first (allocates: for tests and one-off uses).
std::vector<Candidate> select_cameras(const Views& views, const Eigen::Vector3d& X,
                                      const Eigen::Vector3d& n, const Options& opts);

namespace detail {
// Fills scratch.cache for the patch centre X (shared by every orientation at X).
void prepare_centre(const Views& views, const Eigen::Vector3d& X, const Options& opts, Scratch& s);
// Fills scratch.cand with the usable views within the cone of unit n; returns their count.
// Only the first min(k, count) are sorted (partial sort); sort the rest on demand.
int gather_candidates(const Views& views, const Eigen::Vector3d& n, const Options& opts, Scratch& s);
}  // namespace detail

}  // namespace tetmvs::photo
