// Q, the quasi-dense oriented points (paper section 2.3): for every crossing face, its
// best photo-consistent lattice point, with its normal, score and the cameras it is
// photo-consistent in. Written by `photoconsist` (group /points of pc_<i>.h5 and
// scores.h5), read by `label` (visibility votes) and `silhouette-fix`.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace tetmvs {
namespace h5 {
class File;
template <typename R>
class Fields;
}  // namespace h5

struct QPoints {
  std::vector<double> position;        // P x 3, world
  std::vector<float> normal;           // P x 3, unit, outward (towards the cameras)
  std::vector<float> score;            // P, photo-consistency in (T, 1]
  std::vector<std::int64_t> cam_offsets{0};  // P + 1: cameras of point p are
  std::vector<std::int32_t> cams;            //   cams[cam_offsets[p] .. cam_offsets[p+1])
  std::vector<std::int32_t> face;      // P, face of the mesh the point lies on (-1: unknown)

  std::int64_t size() const { return static_cast<std::int64_t>(score.size()); }
  Eigen::Vector3d pos(std::int64_t p) const {
    return {position[3 * p], position[3 * p + 1], position[3 * p + 2]};
  }
  Eigen::Vector3d nrm(std::int64_t p) const {
    return {normal[3 * p], normal[3 * p + 1], normal[3 * p + 2]};
  }
  void add(const Eigen::Vector3d& X, const Eigen::Vector3d& n, float s,
           const std::vector<std::int32_t>& cameras, std::int32_t f);
};

// The datasets of a group holding Q: position (P, 3), normal (P, 3), score, cam_offsets
// (P + 1), cams, face (common/h5fields.h; paths relative to the group).
const h5::Fields<QPoints>& qpoints_fields();
// Writes /points/{position, normal, score, cam_offsets, cams, face}.
void write_qpoints(h5::File& f, const QPoints& q, const std::string& group = "/points");
// Reads and validates them (shapes, camera indices < num_cameras, offsets monotone).
QPoints read_qpoints(const h5::File& f, int num_cameras, const std::string& group = "/points");
// PLY point cloud with normals and a float 'score' property (MeshLab, CloudCompare).
void write_qpoints_ply(const std::filesystem::path& file, const QPoints& q);

}  // namespace tetmvs
