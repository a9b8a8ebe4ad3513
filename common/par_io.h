// Middlebury camera files (<prefix>_par.txt): first line the number of views, then
// one line per image: "name k11..k33 r11..r33 t1 t2 t3" (22 fields).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "common/camera.h"

namespace tetmvs {

// Strict reader. Throws Error("<file>:<line>: <problem>") on a wrong field count,
// a non-numeric or non-finite value, a non-orthonormal R (tolerance rot_tol), a K that
// is not upper triangular with positive focal lengths, a count line that does not
// match the number of views, or a duplicate image name. Image sizes are left 0.
std::vector<Camera> read_par(const std::filesystem::path& file, double rot_tol = 1e-4);

// Writes cameras in the same format, full double precision (round-trips exactly).
void write_par(const std::filesystem::path& file, const std::vector<Camera>& cams);

// Finds the single *_par.txt in a folder; throws when there is none or several.
std::filesystem::path find_par_file(const std::filesystem::path& dir);

}  // namespace tetmvs
