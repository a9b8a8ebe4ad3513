#include "common/tetmesh/stage_common.h"

#include "common/error.h"
#include "common/image.h"
#include "common/log.h"
#include "common/tetmesh/mesh_io.h"
#include "common/tetmesh/slice.h"

namespace tetmvs::tet {

void InspectOptions::add_to(StageCli& cli) {
  cli.add_output("--vtu", vtu, "also write the mesh for ParaView (.vtu; cell data level, colour, new_red)");
  cli.add_output("--slice-png", slice_png, "also write a PNG of the cells cut by a plane, coloured by level");
  cli.add_option("--slice-axis", slice_axis, "normal of the slice plane: x, y or z")
      .one_of({"x", "y", "z"});
  cli.add_option("--slice-at", slice_at, "slice position as a fraction of the grid box along the axis")
      .range(0.0, 1.0);
  cli.add_option("--slice-width", slice_width, "slice image width in pixels").range(16, 16384);
}

void InspectOptions::write(const TetMesh& m) const {
  if (!vtu.empty()) {
    write_vtu(vtu, m);
    info("wrote ", vtu);
  }
  if (!slice_png.empty()) {
    SliceSpec s;
    s.axis = slice_axis == "x" ? 0 : slice_axis == "y" ? 1 : 2;
    const auto box = m.lat.grid_box();
    s.position = box.min()[s.axis] + slice_at * box.sizes()[s.axis];
    s.width = slice_width;
    write_png_rgb(slice_png, render_slice(m, s, colours_by_level(m)));
    info("wrote ", slice_png);
  }
}

}  // namespace tetmvs::tet
