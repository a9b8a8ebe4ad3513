#include "common/photoconsist/files.h"

#include <algorithm>

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

QPoints LeveledPoints::of_level(int lvl) const {
  QPoints out;
  std::vector<std::int32_t> cams;
  for (std::int64_t p = 0; p < q.size(); ++p) {
    if (level[p] != lvl) continue;
    cams.assign(q.cams.begin() + q.cam_offsets[p], q.cams.begin() + q.cam_offsets[p + 1]);
    out.add(q.pos(p), q.nrm(p).cast<double>(), q.score[p], cams, -1);
  }
  return out;
}

int LeveledPoints::last_level() const {
  int last = -1;
  for (const std::int32_t l : level) last = std::max(last, static_cast<int>(l));
  return last;
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
