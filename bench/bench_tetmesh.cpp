// Speed and memory of the adaptive BCC mesh: refine (cells per second, bytes per cell),
// point location and ray walks. Run: bench_tetmesh [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <random>

#include "common/tetmesh/locate.h"
#include "common/tetmesh/refine.h"

using namespace tetmvs::tet;

namespace {

// Active = cells whose vertices straddle the sphere |x| = 0.7 (box [-1,1]^3).
std::vector<std::uint8_t> shell_active(const TetMesh& m, double R = 0.7) {
  std::vector<std::uint8_t> act(m.num_cells(), 0);
  const int L = m.max_cell_level();
#pragma omp parallel for schedule(static, 4096)
  for (std::int32_t c = 0; c < m.num_cells(); ++c) {
    if (m.node_level[m.cell_node[c]] != L) continue;
    double lo = 1e30, hi = 0;
    for (std::int32_t v : m.cell_v[c]) {
      const double r = m.vertex(v).norm();
      lo = std::min(lo, r), hi = std::max(hi, r);
    }
    act[c] = lo <= R && hi >= R;
  }
  return act;
}

TetMesh shell_mesh(int cells, int levels) {
  TetMesh m = build_bcc(lattice_for_box(Eigen::AlignedBox3d(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1)), cells));
  for (int l = 0; l < levels; ++l) m = refine(m, shell_active(m));
  return m;
}

// One refinement step toward the sphere shell; counters: new mesh cells per second and
// bytes of the mesh (all arrays, tree included) per cell.
void BM_RefineShell(benchmark::State& state) {
  const int levels = static_cast<int>(state.range(0));
  const TetMesh m = shell_mesh(8, levels - 1);
  const auto act = shell_active(m);
  std::int64_t cells = 0;
  std::size_t bytes = 0;
  TetMesh r;
  for (auto _ : state) {
    r = refine(m, act);
    cells += r.num_cells();
    bytes = r.memory_bytes();
  }
  state.counters["cells"] = r.num_cells();
  state.counters["cells_per_s"] = benchmark::Counter(static_cast<double>(cells), benchmark::Counter::kIsRate);
  state.counters["bytes_per_cell"] = static_cast<double>(bytes) / r.num_cells();
  const double uniform = double(r.num_level0) * std::pow(8.0, levels);
  state.counters["pct_of_uniform"] = 100.0 * r.num_cells() / uniform;
}
BENCHMARK(BM_RefineShell)->DenseRange(4, 6)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_RefineUniform(benchmark::State& state) {
  const TetMesh m = refine_uniform(build_bcc(lattice_for_box(
                                       Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1)), 16)),
                                   1);
  const std::vector<std::uint8_t> act(m.num_cells(), 1);
  std::int64_t cells = 0;
  for (auto _ : state) {
    const TetMesh r = refine(m, act);
    cells += r.num_cells();
  }
  state.counters["cells_per_s"] = benchmark::Counter(static_cast<double>(cells), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RefineUniform)->Unit(benchmark::kMillisecond)->Iterations(2);

const TetMesh& walk_mesh() {
  static const TetMesh m = shell_mesh(8, 4);
  return m;
}

void BM_Locate(benchmark::State& state) {
  const TetMesh& m = walk_mesh();
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> U(-1, 1);
  std::vector<Eigen::Vector3d> pts(4096);
  for (auto& p : pts) p = Eigen::Vector3d(U(rng), U(rng), U(rng));
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(locate(m, pts[i++ & 4095]));
  state.counters["locates_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Locate);

// Rays from points on the sphere to far "cameras" (as the label stage does).
void BM_WalkRay(benchmark::State& state) {
  const TetMesh& m = walk_mesh();
  std::mt19937 rng(2);
  std::normal_distribution<double> N(0, 1);
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> rays(1024);
  for (auto& r : rays) {
    const Eigen::Vector3d d = Eigen::Vector3d(N(rng), N(rng), N(rng)).normalized();
    r = {0.7 * Eigen::Vector3d(N(rng), N(rng), N(rng)).normalized(), 10.0 * d};
  }
  std::vector<WalkHit> hits;
  std::int64_t cells = 0, n = 0;
  for (auto _ : state) {
    const auto& r = rays[n++ & 1023];
    walk_segment(m, r.first, r.first + r.second, hits);
    cells += static_cast<std::int64_t>(hits.size());
  }
  state.counters["rays_per_s"] = benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsRate);
  state.counters["cells_per_s"] = benchmark::Counter(static_cast<double>(cells), benchmark::Counter::kIsRate);
  state.counters["cells_per_ray"] = static_cast<double>(cells) / std::max<std::int64_t>(n, 1);
}
BENCHMARK(BM_WalkRay);

}  // namespace

BENCHMARK_MAIN();
