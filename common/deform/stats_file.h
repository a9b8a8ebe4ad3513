// deform.h5 as `deform` writes it (schema tetmvs.deform, schemas/deform.md): one table of
// its datasets (/iterations/*, one value per iteration) and the root's attributes.
#pragma once
#include "common/deform/deform.h"
#include "common/h5fields.h"

namespace tetmvs::deform {

const h5::Fields<Result>& stats_fields();

}  // namespace tetmvs::deform
