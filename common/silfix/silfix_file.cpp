#include "common/silfix/silfix_file.h"

#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/fileio.h"
#include "common/image.h"
#include "common/log.h"
#include "common/ply.h"

namespace tetmvs::silfix {
namespace fs = std::filesystem;

namespace {

// A column of /constraints or /views.
template <typename M>
auto constraints_column(M Constraint::*member) {
  return [member](const Outcome& o) { return h5::column(o.fix.constraints, member); };
}
template <typename M>
auto views_column(M ViewStats::*member) {
  return [member](const Outcome& o) { return h5::column(o.fix.views, member); };
}

}  // namespace

const h5::Fields<Outcome>& silfix_fields() {
  static const h5::Fields<Outcome> t =
      h5::Fields<Outcome>()
          .dataset("/cells/label", [](const Outcome& o) -> const auto& { return o.fix.label; })
          .dataset("/cells/reason", [](const Outcome& o) -> const auto& { return o.fix.reason; })
          .dataset("/cells/votes", [](const Outcome& o) -> const auto& { return o.in.votes; })
          .dataset("/cells/inside_evidence", [](const Outcome& o) -> const auto& { return o.in.inside_evidence; })
          .dataset("/cells/outside_evidence", [](const Outcome& o) -> const auto& { return o.in.outside_evidence; })
          .attr("/", "low_votes", [](const Outcome& o) { return o.in.low_votes; })
          .attr("/", "high_votes", [](const Outcome& o) { return o.in.high_votes; })
          .attr("/", "rays", [](const Outcome& o) { return o.in.rays; })
          .attr("/", "boundary", [](const Outcome& o) { return o.in.boundary; })
          .attr("/", "hull_exterior", [](const Outcome& o) { return o.in.hull_exterior; })
          .attr("/", "voted_out", [](const Outcome& o) { return o.in.voted_out; })
          .attr("/", "interior", &Outcome::interior)
          .attr("/", "exterior", &Outcome::exterior)
          .attr("/", "silfix_exterior", [](const Outcome& o) { return o.fix.exterior_added; })
          .attr("/", "silfix_interior", [](const Outcome& o) { return o.fix.interior_added; })
          .attr("/", "silfix_conflicts", [](const Outcome& o) { return o.fix.conflicts; })
          .attr("/", "silfix_already", [](const Outcome& o) { return o.fix.already; })
          .attr("/", "s1_mean_iou", [](const Outcome& o) { return o.s1.mean_iou; })
          .attr("/", "s1_mean_boundary_px", [](const Outcome& o) { return o.s1.mean_boundary_px; })
          .attr("/", "s1_p95_boundary_px", [](const Outcome& o) { return o.s1.p95_boundary_px; })
          .attr("/", "note", &Outcome::note)
          .dataset("/constraints/view", constraints_column(&Constraint::view))
          .dataset("/constraints/u", constraints_column(&Constraint::u))
          .dataset("/constraints/v", constraints_column(&Constraint::v))
          .dataset("/constraints/cell", constraints_column(&Constraint::cell))
          .dataset("/constraints/kind", constraints_column(&Constraint::kind))
          .dataset("/constraints/why", constraints_column(&Constraint::why))
          .dataset("/constraints/omega_front", constraints_column(&Constraint::omega_front))
          .dataset("/constraints/omega_back", constraints_column(&Constraint::omega_back))
          .dataset("/constraints/depth_front", constraints_column(&Constraint::depth_front))
          .dataset("/constraints/depth_back", constraints_column(&Constraint::depth_back))
          .dataset("/views/view", views_column(&ViewStats::view))
          .dataset("/views/iou", views_column(&ViewStats::iou))
          .dataset("/views/s1_px", views_column(&ViewStats::s1_px))
          .dataset("/views/true_px", views_column(&ViewStats::true_px))
          .dataset("/views/too_big_px", views_column(&ViewStats::too_big_px))
          .dataset("/views/too_small_px", views_column(&ViewStats::too_small_px))
          .dataset("/views/small_regions", views_column(&ViewStats::small_regions))
          .dataset("/views/exterior_rays", views_column(&ViewStats::exterior_rays))
          .dataset("/views/interior_rays", views_column(&ViewStats::interior_rays))
          .dataset("/views/straddling", views_column(&ViewStats::straddling))
          .dataset("/views/no_segment", views_column(&ViewStats::no_segment))
          .dataset("/views/multi_segment", views_column(&ViewStats::multi_segment))
          .dataset("/views/weak_peaks", views_column(&ViewStats::weak_peaks))
          .dataset("/views/corner_outside", views_column(&ViewStats::corner_outside))
          .dataset("/views/exterior_added", views_column(&ViewStats::exterior_added))
          .dataset("/views/interior_added", views_column(&ViewStats::interior_added))
          .dataset("/views/conflicts", views_column(&ViewStats::conflicts))
          .dataset("/views/already", views_column(&ViewStats::already));
  return t;
}

std::string summary_line(const Outcome& out) {
  if (out.note) return *out.note;
  const Result& r = out.fix;
  const SilhouetteAgreement& agree = out.s1;
  std::int64_t multi = 0, weak = 0, rays = 0, strad = 0, corner = 0, none = 0;
  for (const auto& st : r.views)
    multi += st.multi_segment, weak += st.weak_peaks, rays += st.interior_rays, strad += st.straddling,
        corner += st.corner_outside, none += st.no_segment;
  std::ostringstream os;
  os << std::fixed << std::setprecision(4) << "S1 mean IoU " << agree.mean_iou << ", boundary error mean "
     << std::setprecision(2) << agree.mean_boundary_px << " px, p95 " << agree.p95_boundary_px << " px; added "
     << r.exterior_added << " exterior (" << strad << " straddling cells left free), " << r.interior_added
     << " interior (" << rays << " rays: " << multi << " several segments, " << none << " none, " << weak
     << " weak peaks, " << corner << " corner outside); " << r.conflicts << " conflicts, " << r.already
     << " already interior";
  return os.str();
}

void write_pictures(const fs::path& dir, const Scene& scene, const Outcome& out, double margin_px) {
  std::vector<cv::Mat> pics;
  std::vector<std::string> caps;
  for (const auto& st : out.fix.views) {
    const int v = st.view;
    cv::Mat pic = view_picture(scene.sil[v], out.fix.s1_masks[v], out.fix.constraints, v, margin_px);
    std::ostringstream name, cap;
    name << "view_" << std::setw(3) << std::setfill('0') << v << ".png";
    write_png_rgb(dir / name.str(), pic);
    cap << "v" << v << " IoU " << std::fixed << std::setprecision(3) << st.iou << " in+" << st.interior_added
        << " ex+" << st.exterior_added;
    pics.push_back(pic);
    caps.push_back(cap.str());
  }
  if (!pics.empty()) write_png_rgb(dir / "sheet.png", contact_sheet(pics, caps));
}

std::string report_agreement(const Scene& scene, const std::vector<std::string>& plys, const fs::path& json_out) {
  nlohmann::json j = nlohmann::json::object();
  std::ostringstream os;
  for (const auto& p : plys) {
    const TriMesh m = read_ply(p);
    const SilhouetteAgreement a = silhouette_agreement(m, scene);
    std::ostringstream line;
    line << std::fixed << std::setprecision(4) << fs::path(p).filename().string() << ": mean IoU " << a.mean_iou
         << ", boundary error mean " << std::setprecision(2) << a.mean_boundary_px << " px, 95th percentile "
         << a.p95_boundary_px << " px (" << a.views.size() << " views)";
    info(line.str());
    os << (os.tellp() > 0 ? "; " : "") << line.str();
    j[fs::path(p).filename().string()] = {{"file", p},
                                           {"views", a.views},
                                           {"iou", a.iou},
                                           {"mean_iou", a.mean_iou},
                                           {"mean_boundary_px", a.mean_boundary_px},
                                           {"p95_boundary_px", a.p95_boundary_px}};
  }
  if (!json_out.empty()) write_text_atomic(json_out, j.dump(2) + "\n");
  return os.str();
}

}  // namespace tetmvs::silfix
