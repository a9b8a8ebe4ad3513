// Per-thread working memory of the photo-consistency measure. Make one per thread
// and pass it to every call: the measure then allocates nothing after its first call.
// Its contents are internal (public only so the measure's files can use them).
#pragma once
#include <Eigen/Core>
#include <vector>

namespace tetmvs::photo {

struct Options;
class Views;

// A view that may see a patch: cos of the angle between the patch normal and the
// direction from the patch centre to the camera centre.
struct Candidate {
  double cos = 0;
  int view = -1;
};
// Order of preference: smallest angle first, ties by lower view index.
inline bool better_candidate(const Candidate& a, const Candidate& b) {
  return a.cos > b.cos || (a.cos == b.cos && a.view < b.view);
}

class Scratch {
 public:
  // Sizes the buffers (done by the measure itself when the sizes change).
  void reserve(int num_views, const Options& opts);

  // --- internal -----------------------------------------------------------
  struct ViewCache {
    Eigen::Vector3d dir;  // unit direction from the patch centre to the camera centre
    Eigen::Vector3d h0;   // homogeneous projection of the patch centre (z = depth)
    bool usable = false;  // in front, centre inside the image (and silhouette if asked)
  };
  std::vector<ViewCache> cache;
  std::vector<Candidate> cand;
  // Samples, transposed: mu (line) or mu*mu (grid) rows of `lanes` floats, one column
  // per usable view (normalized in place). lanes = k rounded up to a multiple of 4.
  std::vector<float> samples;
  std::vector<float> corr;     // k x lanes NCC matrix (row r: view r's NCCs)
  int lanes = 0;
  std::vector<int> views;      // the usable views, in order of preference
  std::vector<float> row;      // one ref's NCCs with its partners
  std::vector<int> row_idx;
  int num_views = -1, k = -1, mu = -1;

  // Set by the caller (not by the measure): when non-null, views i with hidden[i] != 0
  // are not usable for the next patch centres (photoconsist's occlusion test,
  // common/photoconsist/occlusion.h). Must point to num_views flags.
  const unsigned char* hidden = nullptr;
};

}  // namespace tetmvs::photo
