// The minimum cut on the dual graph of the tetrahedral mesh (paper sections 2.1 and 3.1).
//
// Nodes are cells; every interior face f between cells a = face_cell(f,0) and
// b = face_cell(f,1) gives two directed edges: a->b costs phi(omega[2f+0]) (face normal
// from a to b: the outward normal when a is inside and b outside) and b->a costs
// phi(omega[2f+1]). Cells labelled interior are tied to the source and exterior cells to
// the sink with infinite capacity. Instead of infinite edges the graph is contracted:
// every interior cell IS the source, every exterior cell the sink (an exact equivalent
// that keeps the graph small), so the graph's nodes are the free cells only: a face
// between two free cells gives two arcs, a face between a free cell and a labelled one
// (or the mesh boundary: the outside world is exterior) adds its cost to the free cell's
// capacity from the source or to the sink, and a face between an interior and an exterior
// cell is cut whatever happens. Max-flow / min-cut: common/cut/maxflow.h (Boykov-
// Kolmogorov on compact arrays, one net terminal capacity per node). The result is the
// minimum cut whose inside is smallest; its energy is checked against the flow.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "common/param_binding.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs::cut {

enum Label : std::int8_t { kExterior = -1, kFree = 0, kInterior = 1 };

struct CutOptions {
  double lambda = 0.3;  // Eq. 1's weight of the area term
  double sigma = 0.3;   // Eq. 1's sigma
  // Optional visibility term (an extension of the paper; 0 = the paper's graph): a free
  // cell c pays beta * s_c * inside_evidence[c] when it ends outside and
  // kOutsideShare * beta * s_c * outside_evidence[c] when it ends inside, with
  // s_c = volume^(2/3) (an area, like the face costs). It keeps the cut from shrinking onto a
  // few interior seeds.
  double beta = 0.6;
  // The outside evidence (the share of the views that see through a cell) counts half as
  // much as the inside evidence (hidden behind Q's visible side, within its shell, in the
  // views that see the cell): at equal weights it pulls the first cut into convex bodies
  // where a few views see through gaps in Q (docs/architecture.md, "Visibility term").
  static constexpr double kOutsideShare = 0.5;
  const std::vector<float>* inside_evidence = nullptr;
  const std::vector<float>* outside_evidence = nullptr;
  void check() const;  // throws Error on a value outside its documented range

  static constexpr auto params() {  // the fields that hold parameters (common/param_binding.h)
    return std::to_array<ParamField<CutOptions>>({
        {"cut.lambda", &CutOptions::lambda},
        {"cut.sigma", &CutOptions::sigma},
        {"cut.visibility_weight", &CutOptions::beta},
    });
  }
};

struct CutResult {
  std::vector<std::uint8_t> inside;  // per cell: 1 on the source (object) side
  double energy = 0;                 // sum of phi over cut faces
  double data_energy = 0;            // its data part
  double area_energy = 0;            // its lambda * area part
  double cut_area = 0;               // total area of the cut faces
  double visibility_energy = 0;      // the optional visibility term's part of the energy
  double max_flow = 0;               // the flow found (equals energy minus fixed costs)
  std::int64_t cut_faces = 0;
  std::int64_t graph_nodes = 0;  // free cells plus the source and the sink
  std::int64_t graph_edges = 0;  // arcs (two per face between free cells) plus terminal links
  std::int64_t graph_bytes = 0;  // memory of the graph and of the max-flow's work arrays
};

// omega: 2 per face (see top). labels: one per cell.
CutResult min_cut(const tet::TetMesh& mesh, const std::vector<float>& omega,
                  const std::vector<std::int8_t>& labels, const CutOptions& opt);

}  // namespace tetmvs::cut
