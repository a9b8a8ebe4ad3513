// Adjacency of a closed triangle mesh for deform (paper section 3.3): unique edges with
// their two faces, each face's three edges, and each vertex's neighbours and faces
// (compressed rows, sorted). Rebuilt after every remeshing pass; O(F) (counting sort by
// the lower vertex, then small per-vertex sorts).
#pragma once
#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace tetmvs::deform {

struct Topology {
  int num_vertices = 0;
  std::vector<std::array<int, 2>> edge_v;  // edge endpoints, lower index first; sorted
  std::vector<std::array<int, 2>> edge_f;  // the faces on the edge (second -1 on a boundary edge)
  std::vector<std::uint8_t> edge_count;    // faces on the edge (> 2: non-manifold)
  std::vector<std::array<int, 3>> face_e;  // face_e[f][k]: edge from corner k to corner k+1
  std::vector<int> nbr_start, nbr;         // neighbours of v: nbr[nbr_start[v] .. nbr_start[v+1])
  std::vector<int> vf_start, vf;           // faces of v (ascending)

  int num_edges() const { return static_cast<int>(edge_v.size()); }
  int degree(int v) const { return nbr_start[v + 1] - nbr_start[v]; }
  std::span<const int> neighbours(int v) const { return {nbr.data() + nbr_start[v], nbr.data() + nbr_start[v + 1]}; }
  // Edge id of (a, b) or -1 (binary search).
  int find_edge(int a, int b) const;
  bool closed_manifold() const;  // every edge has exactly two faces
};

Topology build_topology(const std::vector<Eigen::Vector3i>& F, int num_vertices);

// `rounds` times, each value replaced by the mean of itself and its neighbours' (all at once:
// the result does not depend on the vertex order or the thread count).
void ring_average(std::vector<double>& x, const Topology& topo, int rounds);
void ring_average(std::vector<Eigen::Vector3d>& x, const Topology& topo, int rounds);

// Each vertex's faces (compressed rows, ascending) and, read from them, its neighbours:
// for local work on a large mesh (deform's untangling and fold collapses), which needs
// the adjacency of a few vertices many times an iteration. One counting sort, no edge list.
struct VertexFaces {
  std::vector<int> start, faces;  // faces of v: faces[start[v] .. start[v+1])
  VertexFaces(const std::vector<Eigen::Vector3i>& F, int num_vertices);
  std::span<const int> of(int v) const { return {faces.data() + start[v], faces.data() + start[v + 1]}; }
  // v's neighbours into out: sorted, no repeats (Topology's row of v)
  void neighbours(const std::vector<Eigen::Vector3i>& F, int v, std::vector<int>& out) const;
};

}  // namespace tetmvs::deform
