#include "structure/structure_options.h"

#include <stdexcept>

#include "core/error.h"

namespace dynref::structure {

void StructureOptions::Check() const {
  const std::string where = "structure options (backbone line_* / plane_* keys)";
  try {
    line.Check();
    plane.Check();
  } catch (const std::invalid_argument& e) {
    throw InputError(where, e.what());
  }
  residual.Check();
  if (line_match_bits < 0 || line_match_bits > 256) throw InputError(where, "line_match_bits must be in 0..256");
  if (!(line_match_angle_deg > 0) || !(plane_match_angle_deg > 0) || !(plane_merge_angle_deg >= 0))
    throw InputError(where, "angle gates must be > 0");
  if (!(line_match_px > 0) || !(plane_match_dist_m > 0) || !(plane_merge_dist_m >= 0))
    throw InputError(where, "distance gates must be > 0");
  if (!(line_collinear_m > 0) || !(line_min_3d_length_m >= 0)) throw InputError(where, "line 3-D tolerances must be > 0");
  if (!(line_count_weight >= 0) || !(plane_count_weight >= 0)) throw InputError(where, "count weights must be >= 0");
}

}  // namespace dynref::structure
