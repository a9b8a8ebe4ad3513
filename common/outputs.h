// The paths a stage reads and writes, checked before it works: every output must be
// writable where it is to go and must not be one of the stage's inputs or another output
// (after resolving symbolic links), so that a stage never destroys its inputs and never
// fails for a reason it could have seen at the start. StageCli (common/stage.h) runs the
// checks on the options declared with add_input / add_output; the CommitGroup
// (common/fileio.h) makes the outputs appear together at the end.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace tetmvs {

// One path argument: the option that gave it ("--out", or a positional's name), the path,
// and whether it names a folder (an output folder the stage fills, an input folder it reads).
struct PathArg {
  std::string option;
  std::filesystem::path path;
  bool folder = false;
};

// Throws Error naming the option and the path when an output path is empty, is a folder
// where a file is expected (or a file where a folder is), lies under something that is not
// a folder, cannot be written (a probe file is created and removed in the folder that will
// hold it, or its nearest existing parent), or resolves to an input or to another output.
void check_output_paths(const std::vector<PathArg>& outputs, const std::vector<PathArg>& inputs);

// Throws Error when `input` (found while reading, e.g. the par file of a dataset folder)
// resolves to one of the outputs.
void check_not_output(const PathArg& input, const std::vector<PathArg>& outputs);

}  // namespace tetmvs
