// Coloured 3-D points of dynref's dense maps (seed 001, Sec. 3.6): the plain types live in
// io/point_cloud.h (PLY I/O, io/ply.h, reads and writes them); dense/ names them here.
#pragma once
#include "io/point_cloud.h"

namespace dynref::dense {

using dynref::ColoredPoint;
using dynref::PointCloud;
using dynref::TriangleMesh;

}  // namespace dynref::dense
