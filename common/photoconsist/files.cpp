#include "common/photoconsist/files.h"

#include "common/error.h"
#include "common/h5io.h"

namespace tetmvs::photoconsist {

void LeveledPoints::append(const QPoints& more, int lvl, bool keep_face) {
  for (std::int64_t p = 0; p < more.size(); ++p) {
    const std::vector<std::int32_t> cams(more.cams.begin() + more.cam_offsets[p],
                                         more.cams.begin() + more.cam_offsets[p + 1]);
    q.add(more.pos(p), more.nrm(p).cast<double>(), more.score[p], cams, keep_face ? more.face[p] : -1);
    level.push_back(lvl);
  }
}

void write_leveled_points(h5::File& f, const LeveledPoints& p, const std::string& g) {
  write_qpoints(f, p.q, g);
  f.write(g + "/level", p.level, {p.level.size()});
}

LeveledPoints read_leveled_points(const h5::File& f, int num_cameras, const std::string& g) {
  LeveledPoints p;
  p.q = read_qpoints(f, num_cameras, g);
  p.level = f.read<std::int32_t>(g + "/level", {p.q.size()}).data;
  return p;
}

}  // namespace tetmvs::photoconsist
