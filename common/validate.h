// Whether a file of a run can be opened as what it is, cheaply (no full read of large
// files): used by `validate`, which pipeline.mk runs to find intermediates damaged after
// they were made (truncated in place, overwritten) so that make rebuilds them.
#pragma once
#include <filesystem>
#include <string>

namespace tetmvs {

// "" when the file looks sound, else the problem (one line, naming the file):
//   .h5    opens as HDF5 and names a tetmvs schema and version on its root;
//   .ply   its header is well formed and the file is long enough for the counts it
//          declares (files up to 8 MiB are read whole);
//   .json  parses as JSON.
// Other files only need to exist.
std::string file_problem(const std::filesystem::path& file);

}  // namespace tetmvs
