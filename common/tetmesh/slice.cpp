// Mesh slice pictures (see slice.h).
#include "common/tetmesh/slice.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace tetmvs::tet {

cv::Mat render_slice(const TetMesh& m, const SliceSpec& s, const std::vector<cv::Vec3b>& colours) {
  require(s.axis >= 0 && s.axis < 3, "render_slice: axis must be 0, 1 or 2");
  require(colours.size() == static_cast<std::size_t>(m.num_cells()), "render_slice: ", colours.size(),
          " colours for ", m.num_cells(), " cells");
  require(s.width >= 16 && s.width <= 16384, "render_slice: width ", s.width, " out of [16, 16384]");
  const int a = s.axis, u = (a + 1) % 3, v = (a + 2) % 3;
  const Eigen::AlignedBox3d box = m.lat.grid_box();
  const double scale = s.width / box.sizes()[u];
  const int height = std::max(16, static_cast<int>(std::lround(box.sizes()[v] * scale)));
  cv::Mat img(height, s.width, CV_8UC3, cv::Scalar(255, 255, 255));
  const double min_edge_px = 4.0;
  const int shift = 4;  // sub-pixel bits for the drawing calls
  const double sub = 1 << shift;
  for (std::int32_t c = 0; c < m.num_cells(); ++c) {
    const Tet& t = m.cell_v[c];
    Eigen::Vector3d p[4];
    double d[4];
    double lo = 1e300, hi = -1e300;
    for (int k = 0; k < 4; ++k) {
      p[k] = m.vertex(t[k]);
      d[k] = p[k][a] - s.position;
      lo = std::min(lo, d[k]), hi = std::max(hi, d[k]);
    }
    if (lo >= 0 || hi <= 0) continue;  // not cut (or only touched)
    std::vector<Eigen::Vector2d> q;
    for (int k = 0; k < 4; ++k)
      if (d[k] == 0) q.emplace_back(p[k][u], p[k][v]);
    for (const auto& e : kEdge) {
      const double da = d[e[0]], db = d[e[1]];
      if ((da < 0 && db > 0) || (da > 0 && db < 0)) {
        const Eigen::Vector3d x = p[e[0]] + (da / (da - db)) * (p[e[1]] - p[e[0]]);
        q.emplace_back(x[u], x[v]);
      }
    }
    if (q.size() < 3) continue;
    Eigen::Vector2d cen = Eigen::Vector2d::Zero();
    for (const auto& x : q) cen += x;
    cen /= static_cast<double>(q.size());
    std::sort(q.begin(), q.end(), [&](const Eigen::Vector2d& x, const Eigen::Vector2d& y) {
      return std::atan2(x.y() - cen.y(), x.x() - cen.x()) < std::atan2(y.y() - cen.y(), y.x() - cen.x());
    });
    std::vector<cv::Point> poly;
    double extent = 0;
    for (const auto& x : q) {
      const double px = (x.x() - box.min()[u]) * scale, py = height - (x.y() - box.min()[v]) * scale;
      poly.emplace_back(static_cast<int>(std::lround(px * sub)), static_cast<int>(std::lround(py * sub)));
      extent = std::max(extent, (x - cen).norm() * scale);
    }
    const cv::Vec3b col = colours[c];
    cv::fillConvexPoly(img, poly, cv::Scalar(col[0], col[1], col[2]), cv::LINE_8, shift);
    if (s.edges && extent >= min_edge_px)
      cv::polylines(img, poly, true, cv::Scalar(60, 60, 60), 1, cv::LINE_8, shift);
  }
  return img;
}

std::vector<cv::Vec3b> colours_by_level(const TetMesh& m) {
  static const cv::Vec3b pal[8] = {{49, 54, 149},  {69, 117, 180}, {116, 173, 209}, {171, 217, 233},
                                   {254, 224, 144}, {253, 174, 97}, {244, 109, 67},  {215, 48, 39}};
  std::vector<cv::Vec3b> out(m.num_cells());
  for (std::int32_t c = 0; c < m.num_cells(); ++c) {
    cv::Vec3b col = pal[std::min<int>(m.node_level[m.cell_node[c]], 7)];
    if (m.cell_colour[c] == kGreen)
      for (int k = 0; k < 3; ++k) col[k] = static_cast<std::uint8_t>((col[k] + 2 * 255) / 3);
    out[c] = col;
  }
  return out;
}

std::vector<cv::Vec3b> colours_by_field(const std::vector<double>& v, double lo, double hi) {
  std::vector<cv::Vec3b> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    double t = hi > lo ? (v[i] - lo) / (hi - lo) : 0.5;
    if (!std::isfinite(t)) t = 0.5;
    t = std::clamp(t, 0.0, 1.0);
    const double r = std::clamp(1.5 - std::abs(4 * t - 3), 0.0, 1.0),
                 g = std::clamp(1.5 - std::abs(4 * t - 2), 0.0, 1.0),
                 b = std::clamp(1.5 - std::abs(4 * t - 1), 0.0, 1.0);
    out[i] = cv::Vec3b(static_cast<std::uint8_t>(255 * r), static_cast<std::uint8_t>(255 * g),
                       static_cast<std::uint8_t>(255 * b));
  }
  return out;
}

std::vector<cv::Vec3b> colours_by_label(const std::vector<int>& labels) {
  static const cv::Vec3b pal[10] = {{200, 200, 200}, {228, 26, 28},  {55, 126, 184}, {77, 175, 74},
                                    {152, 78, 163},  {255, 127, 0},  {255, 255, 51}, {166, 86, 40},
                                    {247, 129, 191}, {153, 153, 153}};
  std::vector<cv::Vec3b> out(labels.size());
  for (std::size_t i = 0; i < labels.size(); ++i)
    out[i] = labels[i] < 0 ? cv::Vec3b(255, 255, 255) : pal[labels[i] % 10];
  return out;
}

}  // namespace tetmvs::tet
