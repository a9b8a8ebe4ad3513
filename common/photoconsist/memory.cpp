#include "common/photoconsist/memory.h"

namespace tetmvs::photoconsist {

namespace {
// The program, its libraries and the thread pools, before any data.
constexpr double kFixedBytes = 64.0 * 1048576.0;
// Per pixel of every view: RGB (3), the float grey image (4), the silhouette (1), the hull
// test's dilated silhouette and its integral image (5), the reduced pyramid level, and the
// lines of sight's depth map (one float per 2 x 2 pixels).
constexpr double kBytesPerPixel = 15;
// Per face of the mesh, beyond the mesh arrays: a level pass holds each face's lattice codes,
// the distinct lattice points with their scores, the face cache and, per crossing face, the
// best oriented point with its cameras (up to two thirds of the faces cross at the finest
// level on dinoRing); the scores pass holds two orientations' scores and the scored flags.
constexpr double kLevelBytesPerFace = 400;
constexpr double kScoresBytesPerFace = 50;
}  // namespace

// Measured peaks (stages.jsonl) on the torus, weakly textured torus, cup and dinoRing, levels
// 0-2 and scores, 640 x 480 x 48 views: a level pass peaks at about 237 MB + 219 bytes per face
// + 309 per crossing face, the scores pass at about 226 MB + 98 bytes per face; the constants
// above stay 0-25 % over every one of them.
double memory_estimate(const MeshCounts& mesh, double pixels, bool scores) {
  return kFixedBytes + mesh.read_bytes() + kBytesPerPixel * pixels +
         (scores ? kScoresBytesPerFace : kLevelBytesPerFace) * static_cast<double>(mesh.faces);
}

}  // namespace tetmvs::photoconsist
