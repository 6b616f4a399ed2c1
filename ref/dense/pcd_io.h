// PCD (Point Cloud Library) files of coloured clouds: "DATA binary", fields x y z rgb (float,
// rgb packed PCL-style as the bits of a uint32 0x00RRGGBB), HEIGHT 1 — what pcl::io::loadPCDFile,
// Open3D and CloudCompare read. Written atomically.
#pragma once
#include <string>

#include "dense/point_cloud.h"

namespace dynref::dense {

void WritePcd(const std::string& path, const PointCloud& cloud);
// Reads back what WritePcd writes (InputError for anything else; class ids are not stored).
PointCloud ReadPcd(const std::string& path);

}  // namespace dynref::dense
