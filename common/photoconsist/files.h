// Files of the photoconsist stage: pc_<i>.h5 (schema "tetmvs.photoconsist",
// schemas/photoconsist.md) and scores.h5 (schema "tetmvs.scores", schemas/scores.md).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/qpoints.h"

namespace tetmvs {
namespace h5 { class File; }

namespace photoconsist {

inline constexpr const char* kLevelSchema = "tetmvs.photoconsist";
inline constexpr int kLevelVersion = 2;
inline constexpr const char* kScoresSchema = "tetmvs.scores";
inline constexpr int kScoresVersion = 1;

// Q with the level each point was found at.
struct LeveledPoints {
  QPoints q;
  std::vector<std::int32_t> level;  // one per point
  void append(const QPoints& more, int lvl, bool keep_face);
  QPoints of_level(int lvl) const;  // the points of one level (faces -1)
  int last_level() const;           // the highest level of a point (-1 when there is none)
};

// write_qpoints plus <group>/level.
void write_leveled_points(h5::File& f, const LeveledPoints& p, const std::string& group);
LeveledPoints read_leveled_points(const h5::File& f, int num_cameras, const std::string& group);

}  // namespace photoconsist
}  // namespace tetmvs
