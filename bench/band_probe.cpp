// The band of agreement around a surface: how photoconsist's lattice-point measure scores
// points moved off a reference surface along its normal. For a sample of points of the
// reference mesh (synth's gt.ply, or a trusted reconstruction of a real set) and offsets of
// a few pixels of the scale scored, prints the share of the points inside the visual hull
// (photoconsist's test) whose score exceeds photo.T, and the share that also is a crest:
// higher than the best orientation's score DELTA pixels either way along its normal
// (photo::score_offset). A
// measure that localises the surface is above T at 0 and below it a few pixels away.
// Measurements: docs/photoconsist.md, "The band on plaster".
//
//   band_probe SCENE.h5 SURFACE.ply [PYRAMID_LEVEL [SAMPLES [DELTA [key=value ...]]]]
//
// Defaults: pyramid level 0 (full images), 500 samples, DELTA 4. The key=value pairs
// override parameters (as --set does), e.g. photo.T=0.8.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "common/params.h"
#include "common/photo/oriented_point.h"
#include "common/photoconsist/hull.h"
#include "common/photoconsist/options.h"
#include "common/ply.h"
#include "common/scene.h"
#include "common/trimesh/sample.h"

using namespace tetmvs;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: band_probe SCENE.h5 SURFACE.ply [PYRAMID_LEVEL [SAMPLES [DELTA [key=value ...]]]]\n");
    return 2;
  }
  try {
    const int pyramid = argc > 3 ? std::atoi(argv[3]) : 0;
    const int samples = argc > 4 ? std::atoi(argv[4]) : 500;
    const double delta = argc > 5 ? std::atof(argv[5]) : 4.0;
    if (pyramid < 0 || pyramid > 6 || samples < 1 || samples > 1000000 || !(delta > 0 && delta <= 32)) {
      std::fprintf(stderr, "band_probe: PYRAMID_LEVEL must lie in 0..6, SAMPLES in 1..1000000, DELTA in (0, 32]\n");
      return 2;
    }
    Params params = Params::defaults();
    for (int a = 6; a < argc; ++a) params.set(argv[a]);
    const photoconsist::Options opts = photoconsist::Options::from_params(params);
    Scene scene = read_scene(argv[1]);
    scene.load_grey();
    const photo::Views full(scene.cams, scene.grey, scene.sil);
    const photo::Views views = full.reduced(pyramid);
    const TriMesh surface = read_ply(argv[2]);
    // sample spacing for about `samples` points
    double area = 0;
    for (const auto& f : surface.F)
      area += 0.5 * (surface.V[f[1]] - surface.V[f[0]]).cross(surface.V[f[2]] - surface.V[f[0]]).norm();
    if (!(area > 0)) {
      std::fprintf(stderr, "band_probe: %s has no surface (no faces or zero area)\n", argv[2]);
      return 1;
    }
    const SurfaceSamples S = sample_surface(surface, std::sqrt(area / samples), 7);
    const std::vector<double> offsets{-32, -16, -8, -4, -2, -1, 0, 1, 2, 4, 8, 16, 32};
    std::vector<long> above(offsets.size(), 0), defined(offsets.size(), 0), in_hull(offsets.size(), 0);
    std::vector<double> sum(offsets.size(), 0.0);
    std::vector<long> crest(offsets.size(), 0);
    photo::Scratch scratch;
    // photoconsist's visual-hull test (full images, photo.hull_margin_px)
    const photoconsist::HullTest hull(full, scene.sil, opts.hull_margin_px);
    for (std::size_t i = 0; i < S.size(); ++i) {
      // one pixel of the scale scored at the point: the nearest view's footprint
      double fp = 1e300;
      for (int v = 0; v < views.size(); ++v) {
        const double depth = views[v].project_h(S.P[i]).z();
        if (depth > 0) fp = std::min(fp, depth * views[v].inv_focal);
      }
      for (std::size_t k = 0; k < offsets.size(); ++k) {
        const Eigen::Vector3d X = S.P[i] + offsets[k] * fp * S.N[i];
        if (!hull.inside(X)) continue;
        ++in_hull[k];
        const photo::PointResult r = photo::score_point(views, X, S.N[i], opts.line, scratch);
        if (!r.valid()) continue;
        ++defined[k];
        sum[k] += r.score;
        if (r.consistent(opts.line)) {
          ++above[k];
          const float lo = photo::score_offset(views, X, S.N[i], r, -delta, opts.line, scratch);
          const float hi = photo::score_offset(views, X, S.N[i], r, delta, opts.line, scratch);
          if (r.score > std::max(lo, hi)) ++crest[k];
        }
      }
    }
    std::printf("%zu samples, pyramid level %d, T = %.2f, crest over +-%.1f px\n", S.size(), pyramid, opts.line.T, delta);
    std::printf("offset_px  in_hull  defined  above_T  share_above  mean_score  crest  share_crest\n");
    for (std::size_t k = 0; k < offsets.size(); ++k)
      std::printf("%9.0f  %7ld  %7ld  %7ld  %11.3f  %10.3f  %5ld  %11.3f\n", offsets[k], in_hull[k], defined[k], above[k],
                  defined[k] ? static_cast<double>(above[k]) / defined[k] : 0.0,
                  defined[k] ? sum[k] / defined[k] : 0.0, crest[k],
                  defined[k] ? static_cast<double>(crest[k]) / defined[k] : 0.0);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "band_probe: %s\n", e.what());
    return 1;
  }
  return 0;
}
