#include "common/budget.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "common/error.h"
#include "common/h5io.h"
#include "common/log.h"

namespace tetmvs {

namespace {
constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
MemoryBudget g_stage_budget;  // bytes 0: none
}  // namespace

void set_stage_memory_budget(const MemoryBudget& b) { g_stage_budget = b; }

void check_declared_bytes(double bytes, std::string_view what) {
  if (g_stage_budget.bytes <= 0 || bytes <= g_stage_budget.bytes) return;
  fail(what, " declares about ", format_bytes(bytes), ", over the memory budget of ", format_bytes(g_stage_budget.bytes),
       " (", g_stage_budget.source, "): the file is damaged, or the budget too small for it");
}

MemoryBudget memory_budget(const Params& p) {
  MemoryBudget b;
  if (const char* env = std::getenv("TETMVS_MEMORY_GB"); env && *env) {
    errno = 0;
    char* end = nullptr;
    const double gb = std::strtod(env, &end);
    require(end != env && *end == '\0' && errno == 0 && std::isfinite(gb) && gb > 0,
            "environment TETMVS_MEMORY_GB='", env, "' must be a positive number of GiB");
    b.bytes = gb * kGiB;
    b.source = "TETMVS_MEMORY_GB";
  } else {
    b.bytes = p.d("resource.memory_gb") * kGiB;
    b.source = "resource.memory_gb";
  }
  return b;
}

std::string format_bytes(double bytes) {
  char buf[64];
  if (bytes >= kGiB) std::snprintf(buf, sizeof buf, "%.3g GiB", bytes / kGiB);
  else std::snprintf(buf, sizeof buf, "%.3g MiB", bytes / (1024.0 * 1024.0));
  return buf;
}

namespace {
double g_largest_estimate = 0;
}  // namespace

double largest_memory_estimate() { return g_largest_estimate; }

void check_memory_budget(const Params& p, double estimated_bytes, std::string_view what,
                         std::string_view hint) {
  const MemoryBudget b = memory_budget(p);
  if (estimated_bytes > g_largest_estimate) g_largest_estimate = estimated_bytes;
  if (estimated_bytes <= b.bytes) {
    info(what, ": estimated memory ", format_bytes(estimated_bytes), " (budget ", format_bytes(b.bytes), ")");
    return;
  }
  // (NaN estimates end here too: never silently within budget)
  fail(what, ": needs about ", format_bytes(estimated_bytes), ", over the memory budget of ", format_bytes(b.bytes),
       " (", b.source, "): ", hint,
       b.source == "resource.memory_gb"
           ? "; or raise the budget (--set resource.memory_gb=N, or TETMVS_MEMORY_GB=N in the environment)"
           : "; or raise the budget (environment TETMVS_MEMORY_GB)");
}

double mesh_bytes(double cells, double faces, double vertices, double nodes) {
  // per vertex: lattice 3x4 + parents 2x4; per node: 4x4 corners + level, parent, child,
  // first cell, cell count; per cell: 4x4 corners, node, colour, new_red, 4x4 faces;
  // per face: 2 half-faces, parent, sub
  return vertices * 20 + nodes * 30 + cells * 38 + faces * 13;
}

double mesh_bytes(double cells) { return mesh_bytes(cells, 2.1 * cells, 0.2 * cells, 1.2 * cells); }

double MeshCounts::read_bytes() const {
  // the arrays, plus while reading: the xyz doubles (24 per vertex) and the int32 reads
  // copied into the arrays, and build_faces' start/order/partner (2 x 16 per cell)
  return mesh_bytes(cells, faces, vertices, nodes) + 24.0 * vertices + 16.0 * cells + 32.0 * cells +
         8.0 * faces;
}

MeshCounts mesh_counts(const std::filesystem::path& mesh_file) {
  const auto f = h5::File::open(mesh_file, "tetmvs.mesh");
  auto rows = [&](const char* name) -> std::int64_t {
    const auto s = f.has(name) ? f.shape_of(name) : h5::Shape{};
    return s.empty() ? 0 : static_cast<std::int64_t>(s[0]);
  };
  MeshCounts c;
  c.cells = rows("/cells");
  c.faces = rows("/faces");
  c.vertices = rows("/vertices_lattice");
  c.nodes = rows("/tree/vertices");
  return c;
}

}  // namespace tetmvs
