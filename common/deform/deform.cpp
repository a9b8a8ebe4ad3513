#include "common/deform/deform.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <numeric>
#include <ctime>
#include <opencv2/imgproc.hpp>

#include "common/deform/forces.h"
#include "common/deform/intersect.h"
#include "common/deform/photometric.h"
#include "common/deform/remesh.h"
#include "common/deform/topology.h"
#include "common/error.h"
#include "common/h5io.h"
#include "common/log.h"
#include "common/photo/views.h"
#include "common/trimesh/check.h"

namespace tetmvs::deform {

namespace {

constexpr int kUntangleRounds = 8;
constexpr int kFoldRounds = 4;
// Rings over which the last photometric steps are averaged before they join the next ones
// (momentum): on a mesh of 1.35-3 px edges about a Gaussian of 5 px (sigma) of the images in use.
constexpr int kMomentumRounds = 12;
// Vertices within this many rings of one whose move an intersection held back carry no
// momentum (about 5-9 px of the images in use).
constexpr int kMomentumHeldRings = 3;
// Rounds of untangling and fold collapses after the last iteration.
constexpr int kCleanupRounds = 4;

// Wall and process CPU seconds (all threads) of the parts of an iteration (logged;
// bench/deform_parts.py sums them).
double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}
struct PartTimer {
  std::array<double, kNumParts> s{}, cpu{};
  std::chrono::steady_clock::time_point t = std::chrono::steady_clock::now();
  double c = process_cpu_seconds();
  void lap(int part) {
    const auto now = std::chrono::steady_clock::now();
    const double cn = process_cpu_seconds();
    s[part] += std::chrono::duration<double>(now - t).count();
    cpu[part] += cn - c;
    t = now;
    c = cn;
  }
};

std::string part_summary(const std::array<double, kNumParts>& s, const std::array<double, kNumParts>& cpu) {
  std::string out;
  for (int p = 0; p < kNumParts; ++p) {
    char b[96];
    std::snprintf(b, sizeof b, "%s%s %.2f/%.2f", p ? ", " : "", kPartNames[p], s[p], cpu[p]);
    out += b;
  }
  return out;
}

double median(std::vector<double> x) {
  if (x.empty()) return 0;
  const size_t k = x.size() / 2;
  std::nth_element(x.begin(), x.begin() + k, x.end());
  return x[k];
}

std::vector<ViewRaster> rasterize_all(const TriMesh& tm, const Scene& scene, int sd_reach) {
  std::vector<ViewRaster> r(scene.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < scene.size(); ++i) r[i] = rasterize_view(tm, scene.cams[i], scene.sil[i], sd_reach);
  return r;
}

double mean_iou(const std::vector<ViewRaster>& r, const Scene& scene) {
  double sum = 0;
  int n = 0;
  for (int i = 0; i < scene.size(); ++i)
    if (scene.has_silhouette(i)) {
      sum += r[i].either > 0 ? static_cast<double>(r[i].agree) / r[i].either : 1.0;
      ++n;
    }
  return n > 0 ? sum / n : -1.0;
}

bool contains(const std::vector<std::pair<int, int>>& sorted, const std::pair<int, int>& p) {
  return std::binary_search(sorted.begin(), sorted.end(), p);
}

void check_input(const TriMesh& m) {
  m.validate("deform input mesh");
  require(!m.F.empty(), "deform input mesh: no triangles");
  const MeshCheck c = check_mesh(m);
  require(c.closed && c.edge_manifold, "deform input mesh: must be closed and edge-manifold (", c.boundary_edges,
          " boundary edges, ", c.nonmanifold_edges, " non-manifold edges)");
  require(c.oriented, "deform input mesh: ", c.misoriented_edges, " edges are used twice in the same direction");
  for (const auto& comp : c.components)
    require(comp.signed_volume > 0, "deform input mesh: a component of ", comp.faces,
            " faces has negative volume (inward-facing triangles)");
}

// Intersections after the faces flagged in `changed` moved: the pairs of `prev` without a
// changed face, merged with `fresh` (the pairs with one, found by the caller); all sorted.
std::vector<std::pair<int, int>> merge_intersections(const std::vector<std::pair<int, int>>& prev,
                                                     const std::vector<char>& changed,
                                                     const std::vector<std::pair<int, int>>& fresh) {
  std::vector<std::pair<int, int>> kept, out;
  for (const auto& p : prev)
    if (!changed[p.first] && !changed[p.second]) kept.push_back(p);
  std::merge(kept.begin(), kept.end(), fresh.begin(), fresh.end(), std::back_inserter(out));
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// Intersections after faces were renumbered and some changed: the pairs of pairs0 whose two
// faces survive unchanged carry over (to_new: each old face's new index, -1 when removed),
// and the changed faces (flags over the new faces) are tested again.
std::vector<std::pair<int, int>> carry_intersections(const std::vector<Eigen::Vector3d>& V,
                                                     const std::vector<Eigen::Vector3i>& F,
                                                     const std::vector<std::pair<int, int>>& pairs0,
                                                     const std::vector<int>& to_new, const std::vector<char>& changed) {
  std::vector<std::pair<int, int>> prev;
  for (const auto& p : pairs0) {
    const int a = to_new[p.first], b = to_new[p.second];
    if (a >= 0 && b >= 0) prev.emplace_back(std::min(a, b), std::max(a, b));
  }
  std::sort(prev.begin(), prev.end());
  return merge_intersections(prev, changed, self_intersections(V, F, changed));
}

// Intersections after remeshing from those before it (pairs0, faces numbered as when
// m.origin's tracking began, nf0 of them).
std::vector<std::pair<int, int>> intersections_after_remesh(const RemeshMesh& m, int nf0,
                                                            const std::vector<std::pair<int, int>>& pairs0) {
  const int nf = static_cast<int>(m.F.size());
  std::vector<int> to_new(nf0, -1);
  std::vector<char> changed(nf, 0);
  for (int f = 0; f < nf; ++f) {
    if (m.origin[f] < 0) changed[f] = 1;
    else to_new[m.origin[f]] = f;
  }
  return carry_intersections(m.V, m.F, pairs0, to_new, changed);
}

// Renumbers vertices along a Morton (Z-order) curve of their positions and sorts the
// faces by their lowest new vertex (ties: old order): neighbours in the mesh become
// neighbours in memory, and so do their pixels in the images and rasters (the rasteriser,
// the photometric force's hit points and the intersection grid are bound by cache misses).
void reorder_for_locality(RemeshMesh& m) {
  const int nv = static_cast<int>(m.V.size()), nf = static_cast<int>(m.F.size());
  if (nv == 0) return;
  Eigen::Vector3d lo = m.V[0], hi = m.V[0];
  for (const auto& x : m.V) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const double ext = std::max((hi - lo).maxCoeff(), 1e-300);
  const auto spread = [](std::uint64_t x) {  // 21 bits -> every third bit
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffull;
    x = (x | x << 16) & 0x1f0000ff0000ffull;
    x = (x | x << 8) & 0x100f00f00f00f00full;
    x = (x | x << 4) & 0x10c30c30c30c30c3ull;
    x = (x | x << 2) & 0x1249249249249249ull;
    return x;
  };
  std::vector<std::pair<std::uint64_t, int>> key(nv);
#pragma omp parallel for schedule(static)
  for (int v = 0; v < nv; ++v) {
    std::uint64_t c = 0;
    for (int d = 0; d < 3; ++d) {
      const double t = std::clamp((m.V[v][d] - lo[d]) / ext, 0.0, 1.0);
      c |= spread(static_cast<std::uint64_t>(t * 2097151.0)) << d;
    }
    key[v] = {c, v};
  }
  std::sort(key.begin(), key.end());
  std::vector<int> id(nv);
  std::vector<Eigen::Vector3d> V(nv);
  std::vector<double> fp(nv), last_step(m.last_step.empty() ? 0 : nv);
  for (int k = 0; k < nv; ++k) {
    const int v = key[k].second;
    id[v] = k;
    V[k] = m.V[v];
    fp[k] = m.fp[v];
    if (!last_step.empty()) last_step[k] = m.last_step[v];
  }
  m.last_step.swap(last_step);
  std::vector<std::pair<int, int>> fk(nf);
  for (int f = 0; f < nf; ++f) {
    const auto& t = m.F[f];
    fk[f] = {std::min({id[t[0]], id[t[1]], id[t[2]]}), f};
  }
  std::sort(fk.begin(), fk.end());
  std::vector<Eigen::Vector3i> F(nf);
  std::vector<int> origin(m.origin.empty() ? 0 : nf);
  for (int k = 0; k < nf; ++k) {
    const auto& t = m.F[fk[k].second];
    F[k] = Eigen::Vector3i(id[t[0]], id[t[1]], id[t[2]]);
    if (!origin.empty()) origin[k] = m.origin[fk[k].second];
  }
  m.V.swap(V);
  m.F.swap(F);
  m.fp.swap(fp);
  m.origin.swap(origin);
}

// Removes self-intersections (made by remeshing, or present in the input) by umbrella
// smoothing of the vertices of intersecting triangles and their neighbours, growing the
// neighbourhood each round; returns the intersections left (sorted). Local: its work grows
// with the pairs' neighbourhoods, beside one pass over the faces per round (the test).
std::vector<std::pair<int, int>> untangle(std::vector<Eigen::Vector3d>& V, const std::vector<Eigen::Vector3i>& F,
                                          std::vector<std::pair<int, int>> pairs, int rounds) {
  if (pairs.empty()) return pairs;
  const int nv = static_cast<int>(V.size());
  const VertexFaces vf(F, nv);
  std::vector<char> mark(nv, 0), changed(F.size(), 0);
  std::vector<int> marked, nbr;
  const auto add = [&](int v) {
    if (!mark[v]) mark[v] = 1, marked.push_back(v);
  };
  for (int r = 0; r < rounds && !pairs.empty(); ++r) {
    for (const auto& p : pairs)
      for (int f : {p.first, p.second})
        for (int k = 0; k < 3; ++k) add(F[f][k]);
    for (int ring = 0; ring < 1 + r / 2; ++ring)
      for (size_t i = 0, n = marked.size(); i < n; ++i) {
        vf.neighbours(F, marked[i], nbr);
        for (int w : nbr) add(w);
      }
    // new positions of the marked vertices from the old ones, then applied
    std::vector<std::pair<int, Eigen::Vector3d>> moved;
    for (int v : marked) {
      vf.neighbours(F, v, nbr);
      if (nbr.empty()) continue;
      Eigen::Vector3d m = Eigen::Vector3d::Zero();
      for (int w : nbr) m += V[w];
      moved.emplace_back(v, 0.5 * V[v] + 0.5 * m / static_cast<double>(nbr.size()));
    }
    for (const auto& [v, x] : moved) V[v] = x;
    for (int v : marked)
      for (int f : vf.of(v)) changed[f] = 1;
    pairs = merge_intersections(pairs, changed, self_intersections(V, F, changed));
    for (int v : marked) {
      mark[v] = 0;
      for (int f : vf.of(v)) changed[f] = 0;
    }
    marked.clear();
  }
  return pairs;
}

// Fold-overs that untangling leaves (sub-pixel pleats within one vertex's fan: the two
// faces' centroids a fraction of a pixel apart, normals nearly opposite; smoothing moves
// the whole pleat but does not open it) are removed by collapsing an edge of each
// intersecting pair (collapse_folds), then untangling what the collapses made; returns the
// number of collapses.
std::int64_t unfold(RemeshMesh& M, std::vector<std::pair<int, int>>& current) {
  std::int64_t total = 0;
  for (int r = 0; r < kFoldRounds && !current.empty(); ++r) {
    const FoldCollapses fc = collapse_folds(M, current);
    if (fc.count == 0) break;
    total += fc.count;
    auto after = carry_intersections(M.V, M.F, current, fc.face_to_new, fc.changed);
    current = untangle(M.V, M.F, std::move(after), kUntangleRounds);
  }
  return total;
}

}  // namespace

Result deform_mesh(const TriMesh& start, const Scene& scene, const Options& opt) {
  opt.check();
  check_input(start);
  require(scene.size() > 0, "deform: the scene has no cameras");
  require(static_cast<int>(scene.grey.size()) == scene.size(), "deform: the scene's grey images are not loaded");
  const int nc = scene.size();

  const double fallback_fp = pixel_footprint(scene.cams, scene.box.center());

  // the photometric force's images, one pyramid level at a time, coarse to fine
  // (Options::photo_level): each level is made when first used and replaces the previous
  const photo::Views views(scene.cams, scene.grey);
  PhotoLevel photo_images;
  photo_images.level = -1;
  const std::vector<std::vector<int>> partners = photometric_partners(
      scene.cams, scene.box.center(), opt.photo_baseline_min_deg, opt.photo_baseline_max_deg, opt.photo_partners);
  std::vector<cv::Mat> sd(nc);
  for (int i = 0; i < nc; ++i)
    if (scene.has_silhouette(i)) sd[i] = signed_distance(scene.sil[i]);

  RemeshMesh M;
  M.V = start.V;
  M.F = start.F;
  M.fp = vertex_footprints(M.V, scene.cams, fallback_fp);
  M.last_step.assign(M.V.size(), 0.0);
  reorder_for_locality(M);

  Result res;
  std::vector<std::pair<int, int>> current = self_intersections(M.V, M.F);  // of the current mesh
  res.start_intersections = static_cast<std::int64_t>(current.size());
  current = untangle(M.V, M.F, current, kUntangleRounds);
  const std::int64_t start_folds = unfold(M, current);
  info("deform: ", M.V.size(), " vertices, ", M.F.size(), " faces, ", res.start_intersections,
       " intersecting triangle pairs at the start (", start_folds, " fold-over collapses), ", scene.num_silhouettes(), " of ", nc, " views with silhouettes");

  for (int it = 0; it < opt.iterations; ++it) {
    const auto t0 = std::chrono::steady_clock::now();
    PartTimer pt;
    IterationStats st;
    st.iteration = it;
    const int nv = static_cast<int>(M.V.size());
    M.fp = vertex_footprints(M.V, scene.cams, fallback_fp);
    pt.lap(kPartFootprints);
    const std::vector<Eigen::Vector3d> N = vertex_normals(M.V, M.F);
    const Topology topo = build_topology(M.F, nv);
    pt.lap(kPartTopology);
    TriMesh tm;
    tm.V = M.V;
    tm.F = M.F;
    const std::vector<ViewRaster> rasters = rasterize_all(tm, scene, opt.sd_reach_px());
    st.silhouette_iou = mean_iou(rasters, scene);
    if (it == 0) res.start_iou = st.silhouette_iou;
    pt.lap(kPartRaster);

    st.photo_level = opt.w_photo > 0 ? opt.photo_level(it) : -1;
    // on the full images the curvature fairing replaces the bi-Laplacian: their whole
    // photometric steps leave a vertex-scale jitter on weak texture (docs/deform.md, "Fairing on
    // the full images")
    const std::vector<Eigen::Vector3d> fs = smooth_force(M.V, topo, N, opt, st.photo_level == 0);
    std::vector<int> rim;
    const std::vector<Eigen::Vector3d> own = silhouette_force(M.V, N, M.fp, scene.cams, sd, rasters, opt, rim);
    // Each correction is shared with the vertex's one-ring (its mean over the ring, zeros
    // included): a rim vertex moved alone raises a crease along its contour generator, and
    // where the images barely hold the surface (plaster) the creases of many views become
    // terraces ("The silhouette over the one-ring", docs/deform.md). The reach below and the
    // photometric force still go by each vertex's own correction.
    std::vector<Eigen::Vector3d> fsil = own;
    ring_average(fsil, topo, 1);
    pt.lap(kPartSmoothSil);
    // The photometric step along the normal; where a vertex has a silhouette correction of its
    // own (disagreement beyond sil_tolerance_px) the silhouettes win: both move a rim vertex
    // across the ray.
    std::vector<double> fphoto;
    if (st.photo_level >= 0) {
      const int l = st.photo_level;
      if (photo_images.level != l) photo_images = make_photo_level(views, scene.cams, l);
      // the loop's rasters serve every level: a reduced level's pixels look along the rays
      // of every 2^l-th full-resolution pixel (subsample)
      std::vector<Raster> reduced(l > 0 ? nc : 0);
#pragma omp parallel for schedule(dynamic, 1)
      for (int i = 0; i < static_cast<int>(reduced.size()); ++i) reduced[i] = subsample(rasters[i].raster, l);
      std::vector<const Raster*> own;
      for (int i = 0; i < nc; ++i) own.push_back(l > 0 ? &reduced[i] : &rasters[i].raster);
      const PhotometricGradient pg = photometric_gradient(M.V, M.F, N, photo_images, partners, opt.photo_window, own);
      fphoto = photometric_steps(pg, topo, l, opt.mesh_level(it), M.fp, opt.photo_noise_floor);
      st.mean_ncc = pg.mean_ncc;
      st.photo_pixels = pg.pixels;
      double sum_px = 0;
      std::int64_t moved = 0;
      for (int v = 0; v < nv; ++v)
        if (fphoto[v] != 0) {
          sum_px += std::abs(fphoto[v]) / M.fp[v];
          ++moved;
        }
      st.photo_moved = nv ? static_cast<double>(moved) / nv : 0;
      st.mean_photo_step_px = moved ? sum_px / static_cast<double>(moved) : 0;
    }
    pt.lap(kPartPhoto);
    // the corrections' reach around the rim (silhouette_spread), while the photometric force
    // works on images reduced four times or more: on the finer ones it places the surface;
    // corrections of half the largest one or more do not spread
    constexpr int kSpreadMinLevel = 2;
    const bool spreading = st.photo_level < 0 || st.photo_level >= kSpreadMinLevel;
    const std::vector<double> fspread = silhouette_spread(
        M.V, N, M.fp, topo, own,
        {spreading ? opt.sil_spread_px : 0, std::ldexp(1.0, opt.mesh_level(it)), 0.5 * opt.sil_max_px});
    // The share of the photometric step taken: w_photo on the reduced images, where the steps
    // of weak windows follow the noise; the whole step on the full images, whose noise floor
    // (photometric_steps) holds those back instead
    const double w_photo = st.photo_level == 0 ? 1.0 : opt.w_photo;
    // Momentum on the reduced images: the photometric steps taken in the last iteration,
    // smoothed over kMomentumRounds rings (about 5 pixels of the images in use), times
    // photo_momentum, join this iteration's. A cut's lid over a cavity, moving down as a
    // whole at a fraction of a pixel an iteration, keeps its pace; steps that follow the
    // noise vary from vertex to vertex and average out ("Momentum", docs/deform.md).
    const bool momentum = !fphoto.empty() && st.photo_level >= 1 && opt.photo_momentum > 0;
    std::vector<double> inertia;
    if (momentum) {
      inertia = M.last_step;
      ring_average(inertia, topo, kMomentumRounds);
    }
    std::vector<double> photo_step(nv, 0.0);  // along the normal, after the clamp
    std::vector<Eigen::Vector3d> move(nv);
    for (int v = 0; v < nv; ++v) {
      Eigen::Vector3d d = fs[v] + opt.w_silhouette * (fsil[v] + fspread[v] * N[v]);
      if (!fphoto.empty() && own[v].squaredNorm() == 0) {
        photo_step[v] = w_photo * fphoto[v] + (momentum ? opt.photo_momentum * inertia[v] : 0.0);
        d += photo_step[v] * N[v];
      }
      const double lim = opt.max_move_px * M.fp[v];
      const double l = d.norm();
      if (l > lim) {
        d *= lim / l;
        photo_step[v] *= lim / l;
      }
      move[v] = d;
    }

    // Apply, halving the steps of vertices of new intersections (retries recheck only
    // the faces whose vertices changed).
    const auto& before = current;
    std::vector<double> scale(nv, 1.0);
    std::vector<Eigen::Vector3d> V1(nv);
    for (int v = 0; v < nv; ++v) V1[v] = M.V[v] + move[v];
    std::vector<char> reduced(nv, 0);
    // every retry's positions lie between M.V and V1: the candidate pairs are found once
    const MotionPairs candidates(M.V, V1, M.F);
    std::vector<std::pair<int, int>> pairs = candidates.intersections(V1);
    for (int attempt = 0;; ++attempt) {
      std::vector<std::pair<int, int>> fresh;
      for (const auto& p : pairs)
        if (!contains(before, p)) fresh.push_back(p);
      if (fresh.empty() || attempt > opt.intersection_retries) break;
      std::vector<char> changed_v(nv, 0);
      for (const auto& p : fresh)
        for (int f : {p.first, p.second})
          for (int k = 0; k < 3; ++k) {
            const int v = M.F[f][k];
            if (reduced[v] == attempt + 1) continue;
            reduced[v] = static_cast<char>(attempt + 1);
            changed_v[v] = 1;
            scale[v] = attempt == opt.intersection_retries ? 0.0 : 0.5 * scale[v];
            V1[v] = M.V[v] + scale[v] * move[v];
          }
      std::vector<char> changed(M.F.size(), 0);
      for (size_t f = 0; f < M.F.size(); ++f)
        changed[f] = changed_v[M.F[f][0]] || changed_v[M.F[f][1]] || changed_v[M.F[f][2]];
      pairs = merge_intersections(pairs, changed, candidates.intersections(V1, changed));
    }
    double sum_move = 0, sum_px = 0, max_px = 0;
    for (int v = 0; v < nv; ++v) {
      const double l = (V1[v] - M.V[v]).norm();
      sum_move += l;
      sum_px += l / M.fp[v];
      max_px = std::max(max_px, l / M.fp[v]);
      st.reduced_vertices += reduced[v] != 0;
      st.rim_vertices += rim[v] > 0;
      st.spread_vertices += fspread[v] != 0;
    }
    // the photometric part of each move made (the next iteration's momentum); none on the full images
    // and none within kMomentumHeldRings of a vertex whose move an intersection held back
    // (a tight spot: pushing on into it leaves tangles that remeshing turns into intersections)
    for (int v = 0; v < nv; ++v) M.last_step[v] = momentum ? photo_step[v] * scale[v] : 0.0;
    if (momentum) {
      std::vector<char> held(nv, 0);
      for (int v = 0; v < nv; ++v) held[v] = reduced[v] != 0;
      for (int r = 0; r < kMomentumHeldRings; ++r) {
        std::vector<char> grown = held;
        for (int v = 0; v < nv; ++v)
          if (held[v])
            for (int w : topo.neighbours(v)) grown[w] = 1;
        held.swap(grown);
      }
      for (int v = 0; v < nv; ++v)
        if (held[v]) M.last_step[v] = 0.0;
    }
    st.mean_move = nv ? sum_move / nv : 0;
    st.mean_move_px = nv ? sum_px / nv : 0;
    st.max_move_px = max_px;
    M.V.swap(V1);
    pt.lap(kPartMove);

    // Remesh.
    M.fp = vertex_footprints(M.V, scene.cams, fallback_fp);
    pt.lap(kPartFootprints);
    // edges in pixels of the next iteration's images
    const double ms = static_cast<double>(1 << opt.mesh_level(it + 1));
    const int nf_moved = static_cast<int>(M.F.size());
    M.origin.resize(nf_moved);
    std::iota(M.origin.begin(), M.origin.end(), 0);
    st.splits = split_long_edges(M, ms * opt.max_edge_px);
    st.collapses = collapse_short_edges(M, ms * opt.min_edge_px, opt.needle_ratio, ms * opt.max_edge_px);
    st.flips = flip_edges(M, opt.flip_dihedral_deg);
    compact(M);
    reorder_for_locality(M);
    pt.lap(kPartRemesh);
    // Remeshing may make intersections (a flip or a collapse in a tight spot): undo them.
    auto after = intersections_after_remesh(M, nf_moved, pairs);
    M.origin.clear();
    pt.lap(kPartRemeshCheck);
    current = untangle(M.V, M.F, std::move(after), kUntangleRounds);
    const std::int64_t folds = unfold(M, current);
    pt.lap(kPartUntangle);
    st.part_seconds = pt.s;
    st.part_cpu_seconds = pt.cpu;
    st.intersections = static_cast<std::int64_t>(current.size());
    st.vertices = static_cast<std::int64_t>(M.V.size());
    st.faces = static_cast<std::int64_t>(M.F.size());
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    info("deform: iteration ", it, ": move ", st.mean_move_px, " px (max ", st.max_move_px, "), photometric level ",
         st.photo_level, " NCC ", st.mean_ncc, " (", st.photo_pixels, " pixels, ", 100 * st.photo_moved, "% moved, |step| ",
         st.mean_photo_step_px, " px), rim ", st.rim_vertices, " (+", st.spread_vertices, " reached), IoU ", st.silhouette_iou, ", ", st.vertices, " v ", st.faces, " f, +",
         st.splits, " -", st.collapses, " ~", st.flips, ", folds -", folds, ", reduced ", st.reduced_vertices, ", intersections ",
         st.intersections, ", ", st.seconds, " s");
    info("deform: iteration ", it, " seconds (wall/cpu): ", part_summary(st.part_seconds, st.part_cpu_seconds));
    res.iterations.push_back(st);
  }

  // The last remeshing's intersections have no next iteration to untangle them: more rounds
  // of untangling and fold collapses, until none is left or kCleanupRounds are spent.
  for (int r = 0; r < kCleanupRounds && !current.empty(); ++r) {
    current = untangle(M.V, M.F, std::move(current), 2 * kUntangleRounds);
    const std::int64_t folds = unfold(M, current);
    info("deform: cleanup ", r, ": ", current.size(), " intersecting triangle pairs left (", folds, " fold-over collapses)");
  }
  res.mesh.V = M.V;
  res.mesh.F = M.F;
  res.final_intersections = static_cast<std::int64_t>(current.size());
  const auto rasters = rasterize_all(res.mesh, scene, opt.sd_reach_px());
  res.final_iou = mean_iou(rasters, scene);
  compute_vertex_normals(res.mesh);
  sample_vertex_colours(res.mesh, scene, opt.visibility_tol_px, &rasters);
  res.footprint = median(vertex_footprints(M.V, scene.cams, fallback_fp));
  return res;
}

void sample_vertex_colours(TriMesh& m, const Scene& scene, double tol_px, const std::vector<ViewRaster>* rasters) {
  require(m.N.size() == m.V.size(), "sample_vertex_colours: the mesh has no vertex normals");
  const int nv = static_cast<int>(m.nv()), nc = scene.size();
  require(!rasters || static_cast<int>(rasters->size()) == nc, "sample_vertex_colours: ", rasters ? rasters->size() : 0,
          " rasters for ", nc, " views");
  // (visibility reads the depths only: the silhouette distance's reach does not matter)
  const auto vis = vertex_visibility(m.V, scene.cams, rasters ? *rasters : rasterize_all(m, scene, 1), tol_px);
  m.C.assign(nv, {128, 128, 128});
  if (static_cast<int>(scene.rgb.size()) != nc) return;
#pragma omp parallel for schedule(static)
  for (int v = 0; v < nv; ++v) {
    const Eigen::Vector3d n = m.N[v].cast<double>();
    int best = -1;
    double bc = 0;
    for (int i = 0; i < nc; ++i) {
      if (!vis[static_cast<size_t>(v) * nc + i] || scene.rgb[i].empty()) continue;
      const double c = n.dot((scene.cams[i].centre() - m.V[v]).normalized());
      if (c > bc) bc = c, best = i;
    }
    if (best < 0) continue;
    const Eigen::Vector2d p = scene.cams[best].project(m.V[v]);
    const cv::Mat& img = scene.rgb[best];
    const double u = std::clamp(p.x(), 0.0, img.cols - 1.0), w = std::clamp(p.y(), 0.0, img.rows - 1.0);
    const int x0 = std::min(static_cast<int>(u), img.cols - 2 < 0 ? 0 : img.cols - 2);
    const int y0 = std::min(static_cast<int>(w), img.rows - 2 < 0 ? 0 : img.rows - 2);
    const int x1 = std::min(x0 + 1, img.cols - 1), y1 = std::min(y0 + 1, img.rows - 1);
    const double fx = u - x0, fy = w - y0;
    for (int ch = 0; ch < 3; ++ch) {
      const double val = (1 - fx) * (1 - fy) * img.at<cv::Vec3b>(y0, x0)[ch] + fx * (1 - fy) * img.at<cv::Vec3b>(y0, x1)[ch] +
                         (1 - fx) * fy * img.at<cv::Vec3b>(y1, x0)[ch] + fx * fy * img.at<cv::Vec3b>(y1, x1)[ch];
      m.C[v][ch] = static_cast<std::uint8_t>(std::clamp(std::lround(val), 0L, 255L));
    }
  }
}

}  // namespace tetmvs::deform
