// photoconsist's memory estimate, checked against the budget before the mesh and the images
// are read (common/budget.h).
#pragma once
#include "common/budget.h"

namespace tetmvs::photoconsist {

// Bytes a photoconsist run needs for a mesh of these counts and views of `pixels` pixels in
// all: a level pass (`scores` false) or the face scores of the finest mesh (`scores` true).
double memory_estimate(const MeshCounts& mesh, double pixels, bool scores);

}  // namespace tetmvs::photoconsist
