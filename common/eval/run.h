// The evaluate stage's work: its command line's values checked and parsed (plan), the
// reconstruction compared with the ground truth or, without one, checked on its own (run),
// and the JSON (schemas/evaluate.md) and the error picture written (write). The measures
// themselves are common/trimesh/evaluate.h and roughness.h.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "common/camera.h"
#include "common/params.h"
#include "common/trimesh/evaluate.h"

namespace tetmvs::eval {

// The paths and options of the command line (empty: not given).
struct Request {
  std::string mesh, gt, cameras, out, png;
  std::string size;        // --size WxH
  std::string thresholds;  // --thresholds t1,t2,...
  std::string box;         // --region-box "minx miny minz maxx maxy maxz"
  std::string labels, tetmesh;
};

// The request's options parsed, with the eval.* parameters.
struct Plan {
  int width = 0, height = 0;  // --size (0: from the cameras)
  EvalOptions options;        // spacing is set by run(), from the cameras' pixel size
};

// Parses --size, --thresholds and --region-box and checks the options against each other
// and the parameters; Error naming the option otherwise.
Plan plan(const Request& q, const Params& p);

// The outputs of a run: the JSON, the error picture (empty without --png) and the summary line.
struct Outcome {
  nlohmann::json json;
  cv::Mat picture;
  std::string summary;
};

// Reads the meshes and cameras and evaluates (within the memory budget of the parameters).
Outcome run(const Request& q, const Plan& plan, const Params& p);

// Writes the JSON to q.out and the picture to q.png (when given), each atomically.
void write(const Request& q, const Outcome& r);

// Cameras from a par file (image size from the first image beside it, or width x height
// when given) or scene.h5.
std::vector<Camera> load_cameras(const std::string& file, int width, int height);

}  // namespace tetmvs::eval
