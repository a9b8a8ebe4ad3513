// What each view sees of every free cell's centre against Q's depth maps (depth_maps.h):
// free space (in front of Q's visible side by the margin), beyond Q's far side, or hidden
// between the two; the soft evidence for the cut; and the per-cell facts the rules test.
#pragma once
#include <cstdint>
#include <vector>

#include "common/label/depth_maps.h"
#include "common/label/geometry.h"
#include "common/scene.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs::label {

struct EvidenceOptions {
  double margin = 0;         // depth margin, world units
  double shell = 0;          // how deep behind Q's visible side the hidden rule reaches (world; infinity: no limit)
  double wall = 0;           // seen free air lies at least this deep behind Q's visible side in every hiding view (world)
  int min_views = 3;
  double free_weight = 2;
  int seen_free_views = 0;   // 0: no seen-free facts (needs DepthMaps exit / entry otherwise)
  double pixel = 1;          // world size of the pixel unit of hidden_depth
};

// Facts per cell (bits of ViewEvidence::facts).
enum Fact : std::uint8_t {
  kHiddenInShell = 1,   // hidden in min_views views, free and beyond in none, within the shell
  kHiddenTooDeep = 2,   // the same, but deeper than the shell
  kFreeInViews = 4,     // free space in min_views views
  kSeenFreeAir = 8,     // free in seen_free_views views, hidden within the wall depth in none, and
                        // behind a wall in half the views hiding it
  kNeverFree = 16,      // free space and beyond Q in no view
};

struct ViewEvidence {
  // clamped to 255; at: views where the centre lies within the margin of Q's visible side
  std::vector<std::uint8_t> free_views, beyond_views, hidden_views, seen_views, at_views;
  std::vector<float> hidden_depth;  // pixels; -1: fewer than min_views views hide it
  std::vector<float> inside, outside;  // soft evidence in [0, 1]
  std::vector<std::uint8_t> facts;     // Fact bits
};

// For the cells whose flag in `of` is set (0 for the others). d: Q's depth maps (with exit /
// entry when o.seen_free_views > 0), consumed (each view's four maps are packed per pixel).
ViewEvidence view_evidence(const tet::TetMesh& m, const MeshPoints& pts, const Scene& s, DepthMaps d,
                           const std::vector<std::uint8_t>& of, const EvidenceOptions& o);

// Lines of sight (extension): where the depth maps see no free space because a point of Q,
// true or false, lies in front in the view, the rays of the points behind it still cross the
// cell. A free cell behind Q (in no min_views views hidden within the shell, and hidden in
// more views than it lies on Q's visible side) takes each ray of Q that crosses it as a view
// seeing through it: outside = min(1, free_weight x max(views free or beyond, rays) / views),
// inside scaled by what is left. A ray counts only toward a view that sees its point: one
// where the point lies at most `shell` behind the visible side of Q's trusted points (those
// scoring at least Q's median), so the false points inside matter do not carve it.
struct SightLines {
  std::vector<std::int32_t> rays;  // per cell, the rays of Q crossing it (cells behind Q only)
  std::int64_t cells = 0;          // cells behind Q that rays cross
  std::int64_t hidden_views = 0;   // views dropped from points of Q that they do not see
  std::int64_t cast = 0;           // rays cast
};
// q: Q after the filters; margin, shell: world units; pixel: the world size of hidden_depth's pixel.
SightLines add_sight_lines(const tet::TetMesh& m, const MeshPoints& pts, const Scene& s, const QPoints& q,
                           const std::vector<std::uint8_t>& free_cell, const EvidenceOptions& o, double cell,
                           ViewEvidence& e);

}  // namespace tetmvs::label
