#include "common/photoconsist/face_cache.h"

#include <algorithm>

#include "common/error.h"
#include "common/h5fields.h"
#include "common/h5io.h"

namespace tetmvs::photoconsist {

std::int64_t FaceCache::find(std::int32_t f) const {
  const auto it = std::lower_bound(face.begin(), face.end(), f);
  return it != face.end() && *it == f ? it - face.begin() : -1;
}

FaceLat FaceCache::face_lat(std::int64_t e) const {
  FaceLat l;
  std::copy_n(vlat.begin() + 9 * e, 9, l.begin());
  return l;
}

void FaceCache::append(std::int32_t f, const FaceLat& lat, int n, const std::uint16_t* c) {
  require(face.empty() || face.back() < f, "photoconsist: cache faces must be appended in ascending order");
  face.push_back(f);
  vlat.insert(vlat.end(), lat.begin(), lat.end());
  divisions.push_back(n);
  codes.insert(codes.end(), c, c + lattice_size(n));
  offsets.push_back(static_cast<std::int64_t>(codes.size()));
}

std::vector<double> lattice_key(const tet::Lattice& lat) {
  return {lat.origin.x(), lat.origin.y(), lat.origin.z(), lat.h,
          static_cast<double>(lat.dims[0]), static_cast<double>(lat.dims[1]), static_cast<double>(lat.dims[2])};
}

bool FaceCache::compatible(const tet::Lattice& lat, const std::string& sig, std::string* why) const {
  if (lattice != lattice_key(lat)) {
    if (why) *why = "it was made on a different level-0 lattice (another mesh lineage)";
    return false;
  }
  if (signature != sig) {
    if (why) *why = "it was made with other options (" + signature + ") than this run (" + sig + ")";
    return false;
  }
  return true;
}

const h5::Fields<FaceCache>& face_cache_fields() {
  static const h5::Fields<FaceCache> t = h5::Fields<FaceCache>()
                                             .dataset("face", &FaceCache::face)
                                             .dataset("vertices", &FaceCache::vlat, 9)
                                             .dataset("divisions", &FaceCache::divisions)
                                             .dataset("offsets", &FaceCache::offsets)
                                             .dataset("codes", &FaceCache::codes)
                                             .attr("", "level", &FaceCache::level)
                                             .attr("", "lattice", &FaceCache::lattice)
                                             .attr("", "signature", &FaceCache::signature)
                                             .attr("", "pyramid", &FaceCache::pyramid);
  return t;
}

void write_face_cache(h5::File& f, const FaceCache& c, const std::string& g) {
  f.create_group(g);
  face_cache_fields().write(f, c, g);
}

FaceCache read_face_cache(const h5::File& f, const std::string& g) {
  const std::string fn = f.path().string();
  require(f.has(g + "/face"), fn, ": no face cache (group ", g, "); is it a photoconsist level file?");
  FaceCache c;
  c.face = f.read<std::int32_t>(g + "/face", {h5::kAny}).data;
  const std::int64_t C = c.size();
  c.vlat = f.read<std::int32_t>(g + "/vertices", {C, 9}).data;
  c.divisions = f.read<std::int32_t>(g + "/divisions", {C}).data;
  c.offsets = f.read<std::int64_t>(g + "/offsets", {C + 1}).data;
  c.codes = f.read<std::uint16_t>(g + "/codes", {h5::kAny}).data;
  c.level = static_cast<int>(f.attr_int(g, "level"));
  c.lattice = f.attr_doubles(g, "lattice");
  c.signature = f.attr_string(g, "signature");
  c.pyramid = static_cast<int>(f.attr_int(g, "pyramid"));
  require(c.pyramid >= 0 && c.pyramid <= 12, fn, ": ", g, " attribute pyramid = ", c.pyramid, " must lie in [0, 12]");
  require(c.offsets[0] == 0 && c.offsets[C] == static_cast<std::int64_t>(c.codes.size()), fn, ": ", g,
          "/offsets must start at 0 and end at the length of ", g, "/codes");
  for (std::int64_t e = 0; e < C; ++e) {
    require(e == 0 || c.face[e - 1] < c.face[e], fn, ": ", g, "/face is not strictly ascending at ", e);
    require(c.divisions[e] >= 1, fn, ": ", g, "/divisions[", e, "] = ", c.divisions[e], " must be >= 1");
    require(c.offsets[e + 1] - c.offsets[e] == lattice_size(c.divisions[e]), fn, ": ", g,
            "/offsets of entry ", e, " do not match its ", c.divisions[e], " divisions");
  }
  return c;
}

}  // namespace tetmvs::photoconsist
