#include "common/cut/cut_file.h"

#include <sstream>

namespace tetmvs::cut {

const h5::Fields<Cut>& cut_fields() {
  static const h5::Fields<Cut> t =
      h5::Fields<Cut>()
          .dataset("/cells/inside", [](const Cut& c) -> const auto& { return c.flow.inside; })
          .dataset("/surface/face", &Cut::face_ids)
          .attr("/", "energy", [](const Cut& c) { return c.flow.energy; })
          .attr("/", "data_energy", [](const Cut& c) { return c.flow.data_energy; })
          .attr("/", "area_energy", [](const Cut& c) { return c.flow.area_energy; })
          .attr("/", "cut_area", [](const Cut& c) { return c.flow.cut_area; })
          .attr("/", "visibility_energy", [](const Cut& c) { return c.flow.visibility_energy; })
          .attr("/", "max_flow", [](const Cut& c) { return c.flow.max_flow; })
          .attr("/", "cut_faces", [](const Cut& c) { return c.flow.cut_faces; })
          .attr("/", "graph_nodes", [](const Cut& c) { return c.flow.graph_nodes; })
          .attr("/", "graph_edges", [](const Cut& c) { return c.flow.graph_edges; })
          .attr("/", "graph_bytes", [](const Cut& c) { return c.flow.graph_bytes; })
          .attr("/", "split_vertices", [](const Cut& c) { return c.surface_stats.split_vertices; })
          .attr("/", "nonmanifold_edges", [](const Cut& c) { return c.surface_stats.nonmanifold_edges; })
          .attr("/", "reglued_edges", [](const Cut& c) { return c.surface_stats.repaired_edges; })
          .attr("/", "split_edges", [](const Cut& c) { return c.surface_stats.split_edges; })
          .attr("/", "voids_filled", [](const Cut& c) { return c.cleanup.voids_filled; })
          .attr("/", "void_exterior_cells", [](const Cut& c) { return c.cleanup.void_exterior_cells; })
          .attr("/", "specks_removed", [](const Cut& c) { return c.cleanup.specks_removed; })
          .attr("/", "components", [](const Cut& c) { return static_cast<std::int64_t>(c.check.components.size()); })
          .attr("/", "closed", [](const Cut& c) { return c.check.closed; })
          .attr("/", "edge_manifold", [](const Cut& c) { return c.check.edge_manifold; });
  return t;
}

std::string summary_line(const Cut& c) {
  const CutResult& r = c.flow;
  const SurfaceStats& st = c.surface_stats;
  const CleanupStats& cs = c.cleanup;
  std::ostringstream os;
  os << r.cut_faces << " faces, " << c.surface.nv() << " vertices, " << c.check.components.size()
     << " components, " << (c.check.closed ? "closed" : "OPEN") << ", "
     << (c.check.edge_manifold ? "edge-manifold" : "NON-MANIFOLD") << " (" << st.split_vertices
     << " split vertices, " << st.nonmanifold_edges << " pinched edges: " << st.repaired_edges << " re-glued, "
     << st.split_edges << " split), " << cs.voids_filled << " voids filled, " << cs.specks_removed
     << " specks removed, energy " << r.energy << " (data " << r.data_energy << ", area " << r.area_energy
     << "), graph " << r.graph_nodes << " nodes " << r.graph_edges << " edges " << r.graph_bytes / 1048576.0
     << " MB";
  return os.str();
}

}  // namespace tetmvs::cut
