// cut1.h5 / cut2.h5 as `cut` writes them (schema tetmvs.cut, schemas/cut.md): one table of
// their datasets and attributes, and the stage's summary sentence.
#pragma once
#include <string>

#include "common/cut/cut_mesh.h"
#include "common/h5fields.h"

namespace tetmvs::cut {

const h5::Fields<Cut>& cut_fields();

// "N faces, V vertices, K components, closed, edge-manifold (...), ..., energy E (data D,
// area A), graph N nodes M edges X MB" (scripts/bench_pipeline.py reads the graph's part).
std::string summary_line(const Cut& c);

}  // namespace tetmvs::cut
