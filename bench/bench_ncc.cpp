// Speed of the photo-consistency measure (common/photo/): the NCC kernel and the
// oriented-point score (14 orientations x 1 x mu line) that photoconsist evaluates
// at millions of lattice points, and the mu x mu face score of the cut.
// Scene: a textured plane seen by a ring of 48 cameras (dinoRing's count), 640 x 480.
#include <benchmark/benchmark.h>

#include <vector>

#include "common/photo/face_score.h"
#include "common/photo/ncc.h"
#include "common/photo/oriented_point.h"
#include "tests/unit/test_photo_scene.h"

using namespace tetmvs;
using namespace tetmvs::photo;

namespace {

std::vector<float> noise(int n, unsigned seed) {
  std::vector<float> v(n);
  for (int i = 0; i < n; ++i) v[i] = static_cast<float>(testing::lattice_hash(i, seed, 7));
  return v;
}

const testing::PlaneScene& ring_scene() {
  // 48 cameras 40 deg from the plane normal, 0.5 m away, f = 800 px (dinoRing-like).
  static const testing::PlaneScene s(Eigen::Vector3d(0, 0, 1), std::vector<double>(48, 40.0), 0.5, 800.0,
                                     640, 480, 0.002, 1);
  return s;
}
const Views& ring_views() {
  static const Views v(ring_scene().cams, ring_scene().grey);
  return v;
}
// The lattice of one face crossing the surface, in lattice order (as photoconsist
// visits it): a 32 x 32 grid one pixel apart on the plane through the origin with
// normal nf, tilted 60 deg from the surface normal. About 1/6 of the points are
// within 3 px of the surface.
struct Points {
  std::vector<Eigen::Vector3d> X, nf;
};
const Points& points() {
  static const Points p = [] {
    Points p;
    const double h = ring_scene().footprint;
    const Eigen::Vector3d nf = Eigen::Vector3d(std::sin(1.05), 0.0, std::cos(1.05)).normalized();
    const Eigen::Vector3d e1(0, 1, 0), e2 = nf.cross(e1);
    for (int j = 0; j < 32; ++j)
      for (int i = 0; i < 32; ++i) {
        p.X.push_back((i - 15.5) * h * e1 + (j - 15.5) * h * e2);
        p.nf.push_back(nf);
      }
    return p;
  }();
  return p;
}

void BM_NccRaw(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  const auto a = noise(n, 1), b = noise(n, 2);
  for (auto _ : st) benchmark::DoNotOptimize(ncc(a.data(), b.data(), n));
  st.SetItemsProcessed(st.iterations());
  st.SetLabel("pairs (normalize both + dot)");
}
BENCHMARK(BM_NccRaw)->Arg(11)->Arg(121);

void BM_NccNormalizedDot(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  auto a = noise(n, 1), b = noise(n, 2);
  normalize_patch(a.data(), n, 1e-3f, a.data());
  normalize_patch(b.data(), n, 1e-3f, b.data());
  for (auto _ : st) {
    benchmark::DoNotOptimize(a.data());
    benchmark::DoNotOptimize(ncc_normalized(a.data(), b.data(), n));
  }
  st.SetItemsProcessed(st.iterations());
  st.SetLabel("pairs (dot of normalized patches)");
}
BENCHMARK(BM_NccNormalizedDot)->Arg(11)->Arg(121);

void BM_ScorePoint(benchmark::State& st) {
  const Views& v = ring_views();
  const Points& p = points();
  Options o;
  o.k = static_cast<int>(st.range(0));
  Scratch scratch;
  size_t i = 0;
  for (auto _ : st) {
    benchmark::DoNotOptimize(score_point(v, p.X[i], p.nf[i], o, scratch));
    i = (i + 1) % p.X.size();
  }
  st.SetItemsProcessed(st.iterations());
  st.SetLabel("lattice points (14 orientations, 48 views)");
}
BENCHMARK(BM_ScorePoint)->Arg(5)->Arg(6)->Arg(8);

// The photoconsist lattice-point kernel with the stage's defaults: 1 x 21 line
// (photo.line_mu), best 12 cameras (photo.point_k, adaptive), 14 orientations.
void BM_ScorePointLine(benchmark::State& st) {
  const Views& v = ring_views();
  const Points& p = points();
  Options o;
  o.mu = static_cast<int>(st.range(0));
  o.k = static_cast<int>(st.range(1));
  o.adaptive_k = true;
  Scratch scratch;
  size_t i = 0;
  for (auto _ : st) {
    benchmark::DoNotOptimize(score_point(v, p.X[i], p.nf[i], o, scratch));
    i = (i + 1) % p.X.size();
  }
  st.SetItemsProcessed(st.iterations());
  st.SetLabel("lattice points (1 x mu line, k cameras, 14 orientations)");
}
BENCHMARK(BM_ScorePointLine)->Args({21, 12})->Args({11, 5});

void BM_ScorePointsBatch(benchmark::State& st) {
  const Views& v = ring_views();
  const Points& p = points();
  std::vector<double> X, nf;
  for (size_t i = 0; i < p.X.size(); ++i) {
    X.insert(X.end(), {p.X[i].x(), p.X[i].y(), p.X[i].z()});
    nf.insert(nf.end(), {p.nf[i].x(), p.nf[i].y(), p.nf[i].z()});
  }
  std::vector<PointResult> out(p.X.size());
  for (auto _ : st) score_points(v, X.data(), nf.data(), static_cast<long>(p.X.size()), Options{}, out.data());
  st.SetItemsProcessed(st.iterations() * static_cast<long>(p.X.size()));
  st.SetLabel("lattice points, all threads (OpenMP)");
}
BENCHMARK(BM_ScorePointsBatch)->UseRealTime();

void BM_FaceScore(benchmark::State& st) {
  const Views& v = ring_views();
  const Points& p = points();
  const double h = 3 * ring_scene().footprint;
  Scratch scratch;
  size_t i = 0;
  for (auto _ : st) {
    const Eigen::Vector3d a = p.X[i], b = a + Eigen::Vector3d(h, 0, 0), c = a + Eigen::Vector3d(0, h, 0);
    benchmark::DoNotOptimize(face_score(v, a, b, c, Options{}, scratch));
    i = (i + 1) % p.X.size();
  }
  st.SetItemsProcessed(st.iterations());
  st.SetLabel("oriented faces (11 x 11 patch)");
}
BENCHMARK(BM_FaceScore);

}  // namespace

BENCHMARK_MAIN();
