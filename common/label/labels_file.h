// labels.h5 as `label` writes it (schema tetmvs.labels, schemas/labels.md): one table of its
// datasets and attributes, which also makes the stage's summary line, and the slice picture.
#pragma once
#include <filesystem>

#include "common/h5fields.h"
#include "common/label/labels.h"

namespace tetmvs::label {

// /cells/* per cell and the counts on the root group; the summary shows the counts
// ("interior=... ; points of Q dropped: ...; cells by rule: ...; turned down: ...").
const h5::Fields<Result>& labels_fields();

// PNG of a slice through the box centre (normal z), cells coloured by label.
void write_label_slice(const std::filesystem::path& png, const tet::TetMesh& mesh, const Scene& scene,
                       const Result& r);

}  // namespace tetmvs::label
