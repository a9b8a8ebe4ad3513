#include "common/qpoints.h"

#include "common/error.h"
#include "common/h5fields.h"
#include "common/h5io.h"
#include "common/ply.h"

namespace tetmvs {

void QPoints::add(const Eigen::Vector3d& X, const Eigen::Vector3d& n, float s,
                  const std::vector<std::int32_t>& cameras, std::int32_t f) {
  for (int k = 0; k < 3; ++k) {
    position.push_back(X[k]);
    normal.push_back(static_cast<float>(n[k]));
  }
  score.push_back(s);
  cams.insert(cams.end(), cameras.begin(), cameras.end());
  cam_offsets.push_back(static_cast<std::int64_t>(cams.size()));
  face.push_back(f);
}

const h5::Fields<QPoints>& qpoints_fields() {
  static const h5::Fields<QPoints> t = h5::Fields<QPoints>()
                                           .dataset("position", &QPoints::position, 3)
                                           .dataset("normal", &QPoints::normal, 3)
                                           .dataset("score", &QPoints::score)
                                           .dataset("cam_offsets", &QPoints::cam_offsets)
                                           .dataset("cams", &QPoints::cams)
                                           .dataset("face", &QPoints::face);
  return t;
}

void write_qpoints(h5::File& f, const QPoints& q, const std::string& g) {
  f.create_group(g);
  qpoints_fields().write(f, q, g);
}

QPoints read_qpoints(const h5::File& f, int num_cameras, const std::string& g) {
  QPoints q;
  const std::string fn = f.path().string();
  q.score = f.read<float>(g + "/score", {h5::kAny}).data;
  const std::int64_t P = q.size();
  q.position = f.read<double>(g + "/position", {P, 3}).data;
  q.normal = f.read<float>(g + "/normal", {P, 3}).data;
  q.cam_offsets = f.read<std::int64_t>(g + "/cam_offsets", {P + 1}).data;
  q.cams = f.read<std::int32_t>(g + "/cams", {h5::kAny}).data;
  q.face = f.read<std::int32_t>(g + "/face", {P}).data;
  require(q.cam_offsets[0] == 0 && q.cam_offsets[P] == static_cast<std::int64_t>(q.cams.size()), fn,
          ": ", g, "/cam_offsets must start at 0 and end at the length of ", g, "/cams");
  for (std::int64_t p = 0; p < P; ++p)
    require(q.cam_offsets[p] <= q.cam_offsets[p + 1], fn, ": ", g, "/cam_offsets is not monotone at ", p);
  for (auto c : q.cams)
    require(c >= 0 && c < num_cameras, fn, ": ", g, "/cams holds camera ", c, " but the scene has ",
            num_cameras, " cameras");
  return q;
}

void write_qpoints_ply(const std::filesystem::path& file, const QPoints& q) {
  TriMesh m;
  const std::int64_t P = q.size();
  m.V.resize(P);
  m.N.resize(P);
  std::vector<float> s(P);
  for (std::int64_t p = 0; p < P; ++p) {
    m.V[p] = q.pos(p);
    m.N[p] = q.nrm(p).cast<float>();
    s[p] = q.score[p];
  }
  m.set_vprop("score", s);
  write_ply(file, m);
}

}  // namespace tetmvs
