#include "common/label/labels_file.h"

#include <string>

#include "common/image.h"
#include "common/tetmesh/slice.h"

namespace tetmvs::label {

namespace {

h5::Fields<Result> make_labels_fields() {
  h5::Fields<Result> t;
  t.dataset("/cells/label", &Result::label)
      .dataset("/cells/reason", &Result::reason)
      .dataset("/cells/votes", &Result::votes)
      .dataset("/cells/inside_evidence", &Result::inside_evidence)
      .dataset("/cells/outside_evidence", &Result::outside_evidence)
      .dataset("/cells/free_views", &Result::free_views)
      .dataset("/cells/beyond_views", &Result::beyond_views)
      .dataset("/cells/hidden_views", &Result::hidden_views)
      .dataset("/cells/seen_views", &Result::seen_views)
      .dataset("/cells/hidden_depth", &Result::hidden_depth)
      .dataset("/cells/sight_rays", &Result::sight_rays)
      .attr("/", "interior", &Result::interior).show()
      .attr("/", "exterior", &Result::exterior).show()
      .attr("/", "rays", &Result::rays).show()
      .attr("/", "low_votes", &Result::low_votes).show()
      .attr("/", "high_votes", &Result::high_votes).show()
      .attr("/", "q_sil_views", &Result::q_sil_views).show()
      .attr("/", "sight_cells", &Result::sight_cells).show()
      .attr("/", "sight_rays", &Result::sight_cast).show()
      .attr("/", "unseen_views", &Result::unseen_views).show()
      .text("; points of Q dropped:");
  for (int k = 0; k < kNumFilters; ++k)
    t.attr("/", std::string("dropped_") + kFilterNames[k], [k](const Result& r) { return r.dropped[k]; })
        .show(kFilterNames[k]);
  t.text("; cells by rule:");
  for (const auto& rule : kRules)
    t.attr("/", std::string("rule_") + rule.name, [id = rule.rule](const Result& r) { return r.count(id); })
        .show(rule.name);
  t.text("; turned down:")
      .attr("/", "too_deep", &Result::too_deep).show()
      .attr("/", "interior_islands", &Result::interior_islands).show()
      .attr("/", "voted_out_near_hull", &Result::voted_out_near_hull).show()
      .attr("/", "seen_free_islands", &Result::seen_free_islands).show();
  return t;
}

}  // namespace

const h5::Fields<Result>& labels_fields() {
  static const h5::Fields<Result> t = make_labels_fields();
  return t;
}

void write_label_slice(const std::filesystem::path& png, const tet::TetMesh& mesh, const Scene& scene,
                       const Result& r) {
  tet::SliceSpec spec;
  spec.axis = 2;
  spec.position = scene.box.center().z();
  const std::vector<int> lab(r.label.begin(), r.label.end());
  write_png_rgb(png, tet::render_slice(mesh, spec, tet::colours_by_label(lab)));
}

}  // namespace tetmvs::label
