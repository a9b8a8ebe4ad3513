#include "common/report/report.h"
#include "common/trimesh/roughness.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <regex>
#include <sstream>

#include "common/error.h"
#include "common/fileio.h"
#include "common/h5io.h"
#include "common/log.h"
#include "common/ply.h"
#include "common/qpoints.h"
#include "common/render/shaded.h"
#include "common/scene.h"

namespace tetmvs::report {
namespace fs = std::filesystem;
using json = nlohmann::json;

std::string base64(const std::string& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (std::uint8_t(in[i]) << 16) | (std::uint8_t(in[i + 1]) << 8) | std::uint8_t(in[i + 2]);
    out += t[v >> 18];
    out += t[(v >> 12) & 63];
    out += t[(v >> 6) & 63];
    out += t[v & 63];
  }
  if (i < in.size()) {
    unsigned v = std::uint8_t(in[i]) << 16;
    if (i + 1 < in.size()) v |= std::uint8_t(in[i + 1]) << 8;
    out += t[v >> 18];
    out += t[(v >> 12) & 63];
    out += i + 1 < in.size() ? t[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

namespace {

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else if (c == '&') o += "&amp;";
    else o += c;
  }
  return o;
}

// Pictures are thumbnails a browser shows at once: one view at most kViewWidth pixels wide,
// a sheet of views at most kSheetWidth, each as PNG or JPEG, whichever is smaller (flat
// colours: PNG; photos: JPEG).
constexpr int kViewWidth = 640, kSheetWidth = 1280;

std::string img_tag(const cv::Mat& rgb, const std::string& caption, int max_width = kViewWidth) {
  cv::Mat bgr, small = rgb;
  if (rgb.cols > max_width)
    cv::resize(rgb, small, {max_width, std::max(1, rgb.rows * max_width / rgb.cols)}, 0, 0, cv::INTER_AREA);
  cv::cvtColor(small, bgr, cv::COLOR_RGB2BGR);
  std::vector<uchar> png, jpg;
  cv::imencode(".png", bgr, png);
  cv::imencode(".jpg", bgr, jpg, {cv::IMWRITE_JPEG_QUALITY, 85});
  const bool use_jpg = jpg.size() < png.size();
  const std::vector<uchar>& buf = use_jpg ? jpg : png;
  return std::string("<figure><img src=\"data:image/") + (use_jpg ? "jpeg" : "png") + ";base64," +
         base64(std::string(buf.begin(), buf.end())) + "\"><figcaption>" + esc(caption) + "</figcaption></figure>\n";
}

std::string img_file(const fs::path& p, const std::string& caption, int max_width = kViewWidth) {
  if (!fs::exists(p)) return "";
  cv::Mat m = cv::imread(p.string(), cv::IMREAD_COLOR);
  if (m.empty()) return "";
  cv::cvtColor(m, m, cv::COLOR_BGR2RGB);
  return img_tag(m, caption, max_width);
}

std::string fmt(double v, int prec = 3) {
  std::ostringstream os;
  os.precision(prec);
  os << v;
  return os.str();
}

// Q projected into a view over the dimmed photo, coloured by score.
cv::Mat points_picture(const Scene& s, const QPoints& q, int v) {
  cv::Mat img = s.rgb[v] * 0.4;
  for (std::int64_t p = 0; p < q.size(); ++p) {
    const Eigen::Vector3d X = q.pos(p);
    if (s.cams[v].depth(X) <= 0) continue;
    const Eigen::Vector2d px = s.cams[v].project(X);
    const int u = int(std::lround(px.x())), w = int(std::lround(px.y()));
    if (u < 0 || w < 0 || u >= img.cols || w >= img.rows) continue;
    const double t = std::clamp((q.score[p] - 0.5) / 0.5, 0.0, 1.0);
    img.at<cv::Vec3b>(w, u) = cv::Vec3b(static_cast<uchar>(255 * t), static_cast<uchar>(255 * (1 - std::abs(2 * t - 1))),
                                        static_cast<uchar>(255 * (1 - t)));
  }
  return img;
}

// One surface's silhouette agreement, for the per-view chart and table.
struct SurfaceAgreement {
  std::string name;
  SilhouetteAgreement a;
};

// IoU per view of each surface as a line chart (x: view, y: IoU from a round value below the
// lowest to 1), views whose true silhouette touches the image border shaded grey.
cv::Mat iou_chart(const std::vector<SurfaceAgreement>& s, int width = kSheetWidth, int height = 300) {
  cv::Mat img(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const std::vector<int>& views = s.front().a.views;
  const int n = static_cast<int>(views.size());
  double lo = 1;
  for (const auto& x : s)
    for (double v : x.a.iou) lo = std::min(lo, v);
  // the y axis starts at a round value below the lowest IoU: 0.99, 0.98, 0.95, 0.9, 0.8, ... 0
  double y0 = 0;
  for (double c : {0.99, 0.98, 0.95, 0.9, 0.8, 0.7, 0.5})
    if (lo >= c + 0.002) {
      y0 = c;
      break;
    }
  const int left = 60, right = 150, top = 12, bottom = 34;
  const double pw = width - left - right, ph = height - top - bottom;
  const auto X = [&](int k) { return left + static_cast<int>(std::lround(n > 1 ? pw * k / (n - 1) : pw / 2)); };
  const auto Y = [&](double iou) {
    return top + static_cast<int>(std::lround(ph * (1 - (std::clamp(iou, y0, 1.0) - y0) / (1 - y0))));
  };
  const double half = n > 1 ? 0.5 * pw / (n - 1) : 0.5 * pw;
  for (int k = 0; k < n; ++k)
    if (s.front().a.cut_by_border[k])
      cv::rectangle(img, {static_cast<int>(X(k) - half), top}, {static_cast<int>(X(k) + half), top + static_cast<int>(ph)},
                    cv::Scalar(225, 225, 225), cv::FILLED);
  const auto text = [&](const std::string& t, cv::Point at, const cv::Scalar& c) {
    cv::putText(img, t, at, cv::FONT_HERSHEY_SIMPLEX, 0.45, c, 1, cv::LINE_AA);
  };
  for (int i = 0; i <= 4; ++i) {  // horizontal grid and its values
    const double v = y0 + (1 - y0) * i / 4;
    cv::line(img, {left, Y(v)}, {left + static_cast<int>(pw), Y(v)}, cv::Scalar(200, 200, 200), 1);
    text(fmt(v, 4), {4, Y(v) + 5}, cv::Scalar(60, 60, 60));
  }
  for (int k = 0; k < n; k += std::max(1, n / 12)) text(std::to_string(views[k]), {X(k) - 8, height - 16}, cv::Scalar(60, 60, 60));
  text("view", {left + static_cast<int>(pw / 2) - 16, height - 2}, cv::Scalar(60, 60, 60));
  const cv::Scalar colours[] = {cv::Scalar(150, 150, 150), cv::Scalar(40, 90, 220), cv::Scalar(30, 160, 60)};  // RGB
  for (std::size_t j = 0; j < s.size(); ++j) {
    const cv::Scalar c = colours[std::min<std::size_t>(j, 2)];
    for (int k = 0; k < n; ++k) {
      if (k > 0) cv::line(img, {X(k - 1), Y(s[j].a.iou[k - 1])}, {X(k), Y(s[j].a.iou[k])}, c, 2, cv::LINE_AA);
      cv::circle(img, {X(k), Y(s[j].a.iou[k])}, 2, c, cv::FILLED, cv::LINE_AA);
    }
    cv::line(img, {width - right + 14, top + 10 + 20 * static_cast<int>(j)}, {width - right + 40, top + 10 + 20 * static_cast<int>(j)}, c, 2);
    text(s[j].name, {width - right + 46, top + 15 + 20 * static_cast<int>(j)}, cv::Scalar(30, 30, 30));
  }
  if (n > 0 && std::any_of(s.front().a.cut_by_border.begin(), s.front().a.cut_by_border.end(), [](char b) { return b; }))
    text("grey: mask touches the border", {width - right + 4, top + 15 + 20 * static_cast<int>(s.size()) + 10}, cv::Scalar(90, 90, 90));
  return img;
}

}  // namespace

std::string build_report(const Options& o) {
  const fs::path R = o.run_dir;
  require(fs::is_directory(R), R.string(), ": run directory does not exist");
  require(fs::exists(R / "scene.h5"), (R / "scene.h5").string(), ": missing; run the pipeline first");
  std::ostringstream h;
  h << "<!doctype html><html><head><meta charset=\"utf-8\"><title>" << esc(o.title) << "</title><style>"
    << "body{font-family:sans-serif;margin:24px;max-width:1280px;color:#222}h1{font-size:22px}"
    << "h2{font-size:18px;border-bottom:1px solid #ccc;margin-top:28px}table{border-collapse:collapse;font-size:13px}"
    << "td,th{border:1px solid #ddd;padding:3px 8px;text-align:left}th{background:#f3f3f3}"
    << "figure{margin:8px 0}img{max-width:100%;border:1px solid #ccc}figcaption{font-size:12px;color:#555}"
    << ".num{text-align:right;font-variant-numeric:tabular-nums}.bad{color:#b00}</style></head><body>\n";
  h << "<h1>" << esc(o.title) << "</h1>\n<p>Run directory: <code>" << esc(fs::absolute(R).string()) << "</code></p>\n";

  const Scene scene = read_scene(R / "scene.h5", true);
  // ---- the run log: the last entry of each stage and output
  std::map<std::string, json> last;
  std::vector<std::string> order;
  if (fs::exists(R / "stages.jsonl")) {
    std::istringstream is(read_file(R / "stages.jsonl"));
    std::string line;
    while (std::getline(is, line)) {
      try {
        const json j = json::parse(line);
        std::string key = j.value("stage", "?");
        const std::string args = j.value("args", "");
        std::smatch m;
        static const std::regex out_re(R"((--out|-o)\s+(\S+))");
        if (std::regex_search(args, m, out_re)) key += " → " + fs::path(m[2].str()).filename().string();
        if (!last.count(key)) order.push_back(key);
        last[key] = j;
      } catch (const std::exception&) {
      }
    }
  }
  // ---- warnings the stages gave (first: they say what the results below may lack)
  {
    std::ostringstream w;
    for (const auto& k : order)
      if (last[k].contains("warnings") && last[k]["warnings"].is_array())
        for (const auto& x : last[k]["warnings"])
          if (x.is_string()) w << "<li><b>" << esc(k) << "</b>: " << esc(x.get<std::string>()) << "</li>\n";
    if (!w.str().empty()) h << "<h2 class=bad>Warnings</h2>\n<ul>\n" << w.str() << "</ul>\n";
  }
  // ---- metrics
  h << "<h2>Results</h2>\n<table><tr><th>surface</th><th>faces</th><th>components</th><th>closed</th>"
    << "<th>silhouette IoU (mean)</th><th>boundary error px (mean / 95%)</th><th>accuracy 90% (pixels at the object; world units)</th>"
    << "<th>completeness (eval.threshold)</th><th>roughness (pixels at the object, median / 90%)</th>"
    << "<th>wrong labels: interior / exterior cells (wholly)</th></tr>\n";
  std::vector<std::pair<std::string, TriMesh>> surfaces;
  std::vector<SurfaceAgreement> agreements;
  for (const char* name : {"cut1", "cut2", "final"}) {
    const fs::path ply = R / (std::string(name) + ".ply");
    if (!fs::exists(ply)) continue;
    TriMesh m = read_ply(ply);
    const auto ag = silhouette_agreement(m, scene);
    const Roughness rough = surface_roughness_px(m, scene.cams, o.roughness_radius_px);
    const double rough_px = rough.radius / o.roughness_radius_px;  // the pixel size there
    h << "<tr><td>" << name << ".ply</td><td class=num>" << m.nf() << "</td>";
    std::string comps = "-", closed = "-", acc = "-", comp = "-", wrong = "-";
    const fs::path ev = R / ("eval_" + std::string(name) + ".json");
    if (fs::exists(ev)) {
      try {
        const json e = json::parse(read_file(ev));
        if (e.contains("reconstruction") && e["reconstruction"].contains("check")) {
          const auto& c = e["reconstruction"]["check"];
          comps = c.value("num_components", json(0)).dump();
          std::string genus;
          if (c.contains("components"))
            for (const auto& k : c["components"]) genus += (genus.empty() ? "" : ",") + k.value("genus", json(-1)).dump();
          if (!genus.empty()) comps += " (genus " + genus + ")";
          closed = c.value("closed", json(false)).dump();
        }
        const auto accuracy_text = [&](double a) {
          return e.contains("pixel_size") && e["pixel_size"].is_number() && e["pixel_size"].get<double>() > 0
                     ? fmt(a / e["pixel_size"].get<double>(), 3) + " px; " + fmt(a, 3)
                     : fmt(a, 3);
        };
        if (e.contains("accuracy") && e["accuracy"]["value"].is_number()) {
          const json& a = e["accuracy"];
          acc = accuracy_text(a["value"].get<double>());
          if (a.contains("value_seen") && a["value_seen"].is_number() &&
              a.value("samples_seen", json(0)) != a.value("samples", json(0)))  // some of the truth unseen
            acc += " (seen part: " + accuracy_text(a["value_seen"].get<double>()) + ")";
        }
        if (e.contains("completeness") && e["completeness"]["value"].is_number())
          comp = fmt(e["completeness"]["value"].get<double>() * 100, 4) + " %";
        if (e.contains("regions"))
          for (const auto& r : e["regions"])
            if (r.value("name", "") != "body" && r.contains("completeness") && r["completeness"]["value"].is_number())
              comp += "; " + r.value("name", std::string("?")) + " " + fmt(r["completeness"]["value"].get<double>() * 100, 4) + " %";
        if (e.contains("labels")) {  // evaluate --labels: the cut's hard labels against the ground truth
          const auto side = [&](const char* k) {
            const json& x = e["labels"][k];
            return x.value("wrong", json(0)).dump() + " (" + x.value("wrong_whole", json(0)).dump() + ")";
          };
          wrong = side("interior") + " / " + side("exterior");
        }
      } catch (const std::exception&) {
      }
    }
    h << "<td>" << esc(comps) << "</td><td>" << esc(closed) << "</td><td class=num>" << fmt(ag.mean_iou, 4)
      << (ag.mean_iou_inside >= 0 && ag.mean_iou_inside != ag.mean_iou
              ? " (" + fmt(ag.mean_iou_inside, 4) + " in the views whose silhouette lies inside the image)"
              : std::string())
      << "</td><td class=num>" << fmt(ag.mean_boundary_px, 3) << " / " << fmt(ag.p95_boundary_px, 3)
      << "</td><td class=num>" << acc << "</td><td class=num>" << comp << "</td><td class=num>"
      << (rough.samples > 0 ? fmt(rough.median / rough_px, 3) + " / " + fmt(rough.p90 / rough_px, 3) : std::string("-"))
      << "</td><td class=num>" << esc(wrong)
      << "</td></tr>\n";
    surfaces.emplace_back(name, std::move(m));
    if (!ag.views.empty()) agreements.push_back({std::string(name) + ".ply", ag});
  }
  h << "</table>\n";
  // ---- silhouette agreement per view: a chart, and the numbers behind it
  if (!agreements.empty()) {
    h << "<h2>Silhouette agreement per view</h2>\n"
      << img_tag(iou_chart(agreements), "silhouette IoU of each surface in each view with a silhouette", kSheetWidth)
      << "<details><summary>IoU per view</summary><table><tr><th>view</th><th>camera</th><th>mask touches the border</th>";
    for (const auto& x : agreements) h << "<th>" << esc(x.name) << "</th>";
    h << "</tr>\n";
    const SilhouetteAgreement& a0 = agreements.front().a;
    for (std::size_t k = 0; k < a0.views.size(); ++k) {
      const int v = a0.views[k];
      h << "<tr><td class=num>" << v << "</td><td>" << esc(scene.cams[v].name) << "</td><td>"
        << (a0.cut_by_border[k] ? "yes" : "no") << "</td>";
      for (const auto& x : agreements) h << "<td class=num>" << fmt(x.a.iou[k], 4) << "</td>";
      h << "</tr>\n";
    }
    h << "</table></details>\n";
  }
  for (const char* name : {"cut1", "cut2", "final"}) {
    const fs::path ev = R / ("eval_" + std::string(name) + ".json");
    if (fs::exists(ev)) {
      json e = json::parse(read_file(ev), nullptr, false);
      if (e.is_discarded()) {
        h << "<p class=bad>" << esc(ev.string()) << ": not valid JSON</p>\n";
        continue;
      }
      if (e.contains("labels"))  // the cell lists are for scripts (examples/inspect_wrong_labels.py)
        for (const char* k : {"wrong_cells", "wrong_whole_cells"})
          if (e["labels"].contains(k)) e["labels"][k] = std::to_string(e["labels"][k].size()) + " cell ids";
      h << "<details><summary>eval_" << name << ".json</summary><pre>" << esc(e.dump(1).substr(0, 6000))
        << "</pre></details>\n";
    }
  }
  // ---- surfaces
  h << "<h2>Surfaces</h2>\n";
  for (auto& [name, m] : surfaces) h << img_tag(render_sheet(m, scene), name + ".ply from four views (red = back faces)", kSheetWidth);
  if (!surfaces.empty()) {  // the photos of the same four views, beside the renders
    std::vector<cv::Mat> tiles;
    for (int v : spread_views(scene.size())) {
      cv::Mat t;
      cv::resize(scene.rgb[v], t, {320, std::max(1, scene.rgb[v].rows * 320 / scene.rgb[v].cols)}, 0, 0, cv::INTER_AREA);
      tiles.push_back(t);
    }
    cv::Mat row;
    cv::hconcat(tiles, row);
    h << img_tag(row, "the photos of the same four views", kSheetWidth);
  }
  for (const char* name : {"cut1", "cut2", "final"}) h << img_file(R / ("eval_" + std::string(name) + ".png"), std::string("error of ") + name + " against the ground truth", kSheetWidth);
  // ---- inputs
  h << "<h2>Input views and silhouettes</h2>\n" << img_file(R / "ingest_contact.png", "images with their silhouettes (green)", kSheetWidth);
  // ---- levels
  h << "<h2>Adaptive mesh per level</h2>\n";
  for (int i = 0; i < 16; ++i) h << img_file(R / ("mesh_" + std::to_string(i) + "_slice.png"), "mesh_" + std::to_string(i) + ": slice coloured by level");
  // ---- Q
  if (fs::exists(R / "scores.h5")) {
    try {
      auto sf = h5::File::open(R / "scores.h5", "tetmvs.scores");
      const QPoints q = read_qpoints(sf, scene.size());
      h << "<h2>Quasi-dense points Q (" << q.size() << ")</h2>\n";
      std::vector<cv::Mat> tiles;
      for (int v : spread_views(scene.size(), 2)) {
        cv::Mat t = points_picture(scene, q, v);  // at full resolution: one point a pixel
        if (t.cols > kViewWidth) cv::resize(t, t, {kViewWidth, std::max(1, t.rows * kViewWidth / t.cols)}, 0, 0, cv::INTER_AREA);
        tiles.push_back(t);
      }
      cv::Mat row;
      cv::hconcat(tiles, row);
      h << img_tag(row, "Q projected into two views, coloured by score (blue low, red high)", kSheetWidth);
    } catch (const Error& e) {
      h << "<p class=bad>" << esc(e.what()) << "</p>";
    }
  }
  h << "<h2>Labels</h2>\n" << img_file(R / "labels_slice.png", "labels: slice through the box centre");
  if (fs::is_directory(R / "silfix")) {
    h << "<h2>Silhouette fix</h2>\n";
    std::vector<fs::path> pngs;
    for (const auto& e : fs::directory_iterator(R / "silfix"))
      if (e.path().extension() == ".png") pngs.push_back(e.path());
    std::sort(pngs.begin(), pngs.end());
    for (const auto& p : pngs) h << img_file(p, p.filename().string());
  }
  // ---- stages
  h << "<h2>Stages: time and memory</h2>\n<table><tr><th>stage</th><th>wall s</th><th>cpu s</th><th>peak MB</th><th>summary</th></tr>\n";
  double total = 0;
  for (const auto& k : order) {
    const json& j = last[k];
    total += j.value("seconds", 0.0);
    h << "<tr><td>" << esc(k) << "</td><td class=num>" << fmt(j.value("seconds", 0.0), 3) << "</td><td class=num>"
      << fmt(j.value("cpu_seconds", 0.0), 3) << "</td><td class=num>" << fmt(j.value("peak_memory_mb", 0.0), 4)
      << "</td><td>" << esc(j.value("summary", "")) << "</td></tr>\n";
  }
  h << "<tr><th>total</th><th class=num>" << fmt(total, 4) << "</th><th></th><th></th><th></th></tr></table>\n";
  // ---- benchmark (scripts/bench_pipeline.py writes bench.json into the run directory)
  if (fs::exists(R / "bench.json")) {
    try {
      const json b = json::parse(read_file(R / "bench.json"));
      h << "<h2>Benchmark</h2>\n<p>scripts/bench_pipeline.py, commit <code>" << esc(b.value("git", "?")) << "</code>, "
        << b["machine"].value("cpus", 0) << " cpus, LEVELS=" << b.value("levels", 0) << "</p>\n"
        << "<table><tr><th>target</th><th>measured</th><th>target</th><th>met</th></tr>\n";
      for (const auto& [k, t] : b["targets"].items())
        h << "<tr><td>" << esc(k) << "</td><td class=num>" << fmt(t.value("measured", 0.0), 4) << "</td><td class=num>"
          << fmt(t.value("target", 0.0), 4) << "</td><td" << (t.value("met", false) ? ">yes" : " class=bad>no") << "</td></tr>\n";
      h << "</table>\n";
      const json& me = b["mesh"];
      if (me.value("cells_final", json()).is_number() && me.value("cells_uniform_same_finest", json()).is_number())
        h << "<p>Final mesh: " << me["cells_final"].get<long long>() << " cells; a uniform BCC mesh of the same finest "
          << "cells would have " << me["cells_uniform_same_finest"].get<long long>() << " ("
          << fmt(100.0 * me.value("fraction_of_uniform", 0.0), 3) << " %).</p>\n";
      h << "<table><tr><th>stage</th><th>level</th><th>wall s</th><th>cpu s</th><th>peak MB</th><th>work counts</th></tr>\n";
      for (const auto& s : b["stages"]) {
        std::string counts;
        for (const auto& [k, v] : s["counts"].items()) counts += (counts.empty() ? "" : ", ") + k + " " + v.dump();
        h << "<tr><td>" << esc(s.value("stage", "")) << "</td><td>" << (s["level"].is_number() ? s["level"].dump() : "")
          << "</td><td class=num>" << fmt(s.value("wall_s", 0.0), 4) << "</td><td class=num>" << fmt(s.value("cpu_s", 0.0), 4)
          << "</td><td class=num>" << fmt(s.value("peak_memory_mb", 0.0), 4) << "</td><td>" << esc(counts) << "</td></tr>\n";
      }
      h << "</table>\n";
      // synthetic scenes: per level, the crossing faces against the faces the true surface
      // crosses (the surfaces' accuracy is in the results table)
      const json q = b.value("quality", json::object());
      if (q.contains("crossing_faces")) {
        h << "<table><tr><th>level</th><th>faces the surface crosses</th><th>found of them (recall)</th>"
          << "<th>crossing faces found</th><th>within two cells (precision)</th><th>active cells</th>"
          << "<th>of them away from the surface (in free space)</th></tr>\n";
        for (const auto& r : q["crossing_faces"]) {
          h << "<tr><td>" << r.value("level", 0) << "</td><td class=num>" << r.value("gt_crossed", 0)
            << "</td><td class=num>" << r.value("found", 0) << " (" << fmt(r.value("recall", 0.0), 4) << ")</td><td class=num>"
            << r.value("crossing", 0) << "</td><td class=num>" << r.value("crossing_near", 0) << " ("
            << fmt(r.value("precision", 0.0), 4) << ")</td>";
          if (r.contains("active"))  // benchmarks written before these counts existed lack them
            h << "<td class=num>" << r.value("active", 0) << "</td><td class=num>" << r.value("active_far", 0) << " ("
              << r.value("active_far_air", 0) << ")</td></tr>\n";
          else
            h << "<td>-</td><td>-</td></tr>\n";
        }
        h << "</table>\n";
      }
    } catch (const std::exception& e) {
      h << "<p class=bad>bench.json unreadable: " << esc(e.what()) << "</p>\n";
    }
  }
  // ---- parameters
  h << "<h2>Parameters</h2>\n<table><tr><th>file</th><th>parameters</th></tr>\n";
  std::vector<fs::path> h5s;
  for (const auto& e : fs::directory_iterator(R))
    if (e.path().extension() == ".h5") h5s.push_back(e.path());
  std::sort(h5s.begin(), h5s.end());
  for (const auto& p : h5s) {
    try {
      auto f = h5::File::open(p);
      std::string params = f.params().dump();
      h << "<tr><td>" << esc(p.filename().string()) << "</td><td><code>" << esc(params) << "</code></td></tr>\n";
    } catch (const Error&) {
    }
  }
  h << "</table>\n</body></html>\n";
  return h.str();
}

}  // namespace tetmvs::report
