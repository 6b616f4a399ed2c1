// PLY writer for coloured point clouds: "ply / format binary_little_endian 1.0" (or ascii),
// one element "vertex" with float x y z and uchar red green blue -- the layout PCL
// (pcl::io::loadPLYFile), Open3D (read_point_cloud) and CloudCompare read natively.
// Written atomically (temp + rename). ASCII floats use FormatDouble17 of the float value.
#pragma once
#include <string>

#include "dense/point_cloud.h"

namespace dynref::dense {

enum class PlyFormat { kBinaryLittleEndian, kAscii };

void WritePly(const std::string& path, const PointCloud& cloud,
              PlyFormat format = PlyFormat::kBinaryLittleEndian,
              const std::string& comment = "");

// Reads back what WritePly writes (both formats; used by tests and `dynref` checks).
// Throws InputError for anything else.
PointCloud ReadPly(const std::string& path);

}  // namespace dynref::dense
