#include "common/label/evidence.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>

#include "common/label/votes.h"

namespace tetmvs::label {

ViewEvidence view_evidence(const tet::TetMesh& m, const MeshPoints& pts, const Scene& s, DepthMaps d,
                           const std::vector<std::uint8_t>& of, const EvidenceOptions& o) {
  const std::int32_t C = m.num_cells();
  ViewEvidence e;
  e.inside.assign(C, 0.0f);
  e.outside.assign(C, 0.0f);
  for (auto* a : {&e.free_views, &e.beyond_views, &e.hidden_views, &e.seen_views, &e.at_views, &e.facts}) a->assign(C, 0);
  e.hidden_depth.assign(C, -1.0f);
  const bool exits = o.seen_free_views > 0;
  const auto u8 = [](int n) { return static_cast<std::uint8_t>(std::min(n, 255)); };
  // Cells in chunks of nearby cells (the mesh's cell order is spatially coherent), each chunk
  // view by view: the depth maps' pixels a chunk reads stay in the cache.
  constexpr std::int32_t kChunk = 256;
  const int V = s.size();
  // per view and pixel the four depths together (one cache line per lookup): front, back, near, far
  std::vector<cv::Mat> packed(V);
#pragma omp parallel for schedule(dynamic, 1)
  for (int v = 0; v < V; ++v) {
    cv::merge(std::vector<cv::Mat>{d.front[v], d.back[v], d.near[v], d.far[v]}, packed[v]);
    d.front[v].release(), d.back[v].release(), d.near[v].release(), d.far[v].release();
  }
  struct Counts {
    int hidden, free_space, beyond, seen, outside_views, wall_hidden, exited, gaps, at;
  };
#pragma omp parallel
  {
    std::vector<Counts> n(kChunk);
    std::vector<double> gaps(static_cast<std::size_t>(kChunk) * V);  // depth behind Q's visible side, per hiding view
    // per view, the chunk's cells that project into the image: their index in the chunk, depth,
    // pixel (offset in the image) and the four depths there, gathered in a loop of their own so
    // that the lookups, which miss the cache, overlap
    std::vector<std::int32_t> at(kChunk), pix(kChunk);
    std::vector<double> zs(kChunk);
    std::vector<cv::Vec4f> px(kChunk);
#pragma omp for schedule(dynamic, 4)
    for (std::int32_t c0 = 0; c0 < C; c0 += kChunk) {
      const std::int32_t c1 = std::min(C, c0 + kChunk);
      std::fill(n.begin(), n.end(), Counts{});
      for (int v = 0; v < V; ++v) {
        const Camera& cam = s.cams[v];
        const cv::Vec4f* depths = packed[v].ptr<cv::Vec4f>(0);
        std::int32_t seen = 0;
        for (std::int32_t c = c0; c < c1; ++c) {
          double z;
          int u, w;
          if (!of[c] || !nearest_pixel(cam, pts.centroid[c], z, u, w)) continue;
          at[seen] = c - c0, zs[seen] = z, pix[seen++] = w * cam.width + u;
        }
        for (std::int32_t i = 0; i < seen; ++i) px[i] = depths[pix[i]];
        for (std::int32_t i = 0; i < seen; ++i) {
          const double z = zs[i];
          Counts& k = n[at[i]];
          const float df = px[i][0], db = px[i][1], dn = px[i][2], dx = px[i][3];
          const bool is_free = dn != 0 && z < dn - o.margin, is_beyond = dx != 0 && z > dx + o.margin;
          k.free_space += is_free;
          k.at += df != 0 && std::abs(z - df) <= o.margin;
          k.beyond += is_beyond;
          k.outside_views += is_free || is_beyond;
          if (df != 0 && db != 0 && z > df + o.margin && z < db - o.margin) {
            ++k.hidden;
            gaps[static_cast<std::size_t>(at[i]) * V + k.gaps++] = z - df;
            k.wall_hidden += z - df <= o.wall;
            if (exits) {
              const float ex = d.exit[v].ptr<float>(0)[pix[i]], en = d.entry[v].ptr<float>(0)[pix[i]];
              k.exited += ex != 0 && ex < z - o.margin && (en == 0 || en > z - o.margin);
            }
          }
          ++k.seen;
        }
      }
      for (std::int32_t c = c0; c < c1; ++c) {
        if (!of[c]) continue;
        const Counts& k = n[c - c0];
        e.free_views[c] = u8(k.free_space);
        e.beyond_views[c] = u8(k.beyond);
        e.hidden_views[c] = u8(k.hidden);
        e.seen_views[c] = u8(k.seen);
        e.at_views[c] = u8(k.at);
        // the depth reached in min_views of the hiding views (robust to a stray point of Q)
        double shallowest = -1;
        if (k.gaps >= o.min_views) {
          double* g = gaps.data() + static_cast<std::size_t>(c - c0) * V;
          std::nth_element(g, g + (o.min_views - 1), g + k.gaps);
          shallowest = g[o.min_views - 1];
        }
        e.hidden_depth[c] = shallowest < 0 ? -1.0f : static_cast<float>(shallowest / o.pixel);
        if (k.seen > 0) {
          const double out = std::min(1.0, o.free_weight * k.outside_views / k.seen);
          e.outside[c] = static_cast<float>(out);
          // inside evidence, like the interior label, only within the shell behind Q: deeper
          // lies the matter of a thick body or the air of a cavity behind false points alike
          const bool too_deep = shallowest > o.shell;
          e.inside[c] = too_deep ? 0.0f : static_cast<float>((1.0 - out) * k.hidden / k.seen);
        }
        std::uint8_t f = 0;
        if (k.free_space == 0 && k.beyond == 0) {
          f |= kNeverFree;
          if (k.hidden >= o.min_views) f |= shallowest <= o.shell ? kHiddenInShell : kHiddenTooDeep;
        }
        if (k.free_space >= o.min_views) f |= kFreeInViews;
        if (exits && k.free_space >= o.seen_free_views && k.wall_hidden == 0 && k.exited >= 0.5 * k.hidden)
          f |= kSeenFreeAir;
        e.facts[c] = f;
      }
    }
  }
  return e;
}

namespace {

// Q with each point's views reduced to those that see it: the point lies at most `shell`
// behind the visible side of the points scoring at least Q's median. Points left without a
// view are dropped.
QPoints seen_points(const Scene& s, const QPoints& q, double cell, double shell, std::int64_t& dropped_views) {
  std::vector<float> sc = q.score;
  std::nth_element(sc.begin(), sc.begin() + static_cast<std::ptrdiff_t>(sc.size() / 2), sc.end());
  const float median = sc[sc.size() / 2];
  std::vector<std::uint8_t> weak(q.size());
  for (std::int64_t p = 0; p < q.size(); ++p) weak[p] = q.score[p] < median;
  const DepthMaps trusted = q_visible_side(s, keep_points(q, weak), cell);
  QPoints out;
  std::vector<std::int32_t> views;
  for (std::int64_t p = 0; p < q.size(); ++p) {
    const Eigen::Vector3d X = q.pos(p);
    views.clear();
    for (std::int64_t k = q.cam_offsets[p]; k < q.cam_offsets[p + 1]; ++k) {
      const int v = q.cams[k];
      double z;
      int u, w;
      const bool in_image = nearest_pixel(s.cams[v], X, z, u, w);
      const float front = in_image ? trusted.front[v].at<float>(w, u) : 0.0f;
      if (in_image && (front == 0 || front >= z - shell))
        views.push_back(v);
      else
        ++dropped_views;
    }
    if (!views.empty()) out.add(X, q.nrm(p), q.score[p], views, q.face[p]);
  }
  return out;
}

}  // namespace

SightLines add_sight_lines(const tet::TetMesh& m, const MeshPoints& pts, const Scene& s, const QPoints& q,
                           const std::vector<std::uint8_t>& free_cell, const EvidenceOptions& o, double cell,
                           ViewEvidence& e) {
  const std::int32_t C = m.num_cells();
  SightLines out;
  if (q.size() == 0) {
    out.rays.assign(C, 0);
    return out;
  }
  const double shell_px = o.shell / o.pixel;
  std::vector<std::uint8_t> behind(C, 0);
  for (std::int32_t c = 0; c < C; ++c) {
    const bool in_shell = e.hidden_depth[c] >= 0 && e.hidden_depth[c] <= shell_px;
    behind[c] = free_cell[c] && e.seen_views[c] > 0 && !in_shell && e.hidden_views[c] > e.at_views[c];
  }
  const QPoints seen = seen_points(s, q, cell, o.shell, out.hidden_views);
  out.rays = visibility_votes(m, s, seen, o.margin, &out.cast, &behind, &pts);
  for (std::int32_t c = 0; c < C; ++c) {
    if (!behind[c] || out.rays[c] == 0) continue;
    ++out.cells;
    const double before = e.outside[c];
    const double after = std::min(1.0, o.free_weight * out.rays[c] / e.seen_views[c]);
    if (after <= before) continue;
    e.inside[c] = before < 1 ? static_cast<float>(e.inside[c] * (1 - after) / (1 - before)) : 0.0f;
    e.outside[c] = static_cast<float>(after);
  }
  return out;
}

}  // namespace tetmvs::label
