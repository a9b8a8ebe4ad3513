// The face cache handed from one level to the next (group /cache of pc_<i>.h5,
// schemas/photoconsist.md): for selected faces of mesh_i, the lattice codes of
// face_lattice.h. At level i+1 a face whose face_parent is a cached face of mesh_i and
// whose face_sub says it is that face or one of its quarters takes its codes from the
// parent's sub-lattice instead of scoring its points again.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/photoconsist/face_lattice.h"
#include "common/tetmesh/tetmesh.h"

namespace tetmvs {
namespace h5 {
class File;
template <typename R>
class Fields;
}  // namespace h5

namespace photoconsist {

struct FaceCache {
  std::vector<std::int32_t> face;        // C, face id in the mesh it was made on, ascending
  std::vector<std::int32_t> vlat;        // C x 9, lattice coordinates of the face's vertices
  std::vector<std::int32_t> divisions;   // C, n
  std::vector<std::int64_t> offsets{0};  // C + 1, into codes
  std::vector<std::uint16_t> codes;      // lattice codes, lattice_size(n) per face

  // Validity of the cache for a run: the mesh lattice and the options' signature.
  std::vector<double> lattice;  // origin xyz, h, dims xyz (as doubles)
  std::string signature;        // Options::cache_signature()
  int level = -1;               // level of the mesh the faces belong to
  int pyramid = 0;              // image-pyramid level the codes were scored on (level_scale.h)

  std::int64_t size() const { return static_cast<std::int64_t>(face.size()); }
  // Entry of face id f, or -1.
  std::int64_t find(std::int32_t f) const;
  FaceLat face_lat(std::int64_t e) const;
  const std::uint16_t* codes_of(std::int64_t e) const { return codes.data() + offsets[e]; }
  // Appends an entry (faces must come in ascending order).
  void append(std::int32_t f, const FaceLat& lat, int n, const std::uint16_t* c);
  // True when the cache was made on the same lattice with the same options.
  bool compatible(const tet::Lattice& lat, const std::string& sig, std::string* why) const;
};

std::vector<double> lattice_key(const tet::Lattice& lat);

// The group of a face cache (paths relative to it): datasets face, vertices, divisions,
// offsets, codes and attributes level, lattice, signature, pyramid (common/h5fields.h).
const h5::Fields<FaceCache>& face_cache_fields();
// Writes them to group `g` (default /cache).
void write_face_cache(h5::File& f, const FaceCache& c, const std::string& g = "/cache");
FaceCache read_face_cache(const h5::File& f, const std::string& g = "/cache");

}  // namespace photoconsist
}  // namespace tetmvs
