// PLY reader/writer for coloured point clouds: "ply / format binary_little_endian 1.0" (or ascii),
// one element "vertex" with float x y z and uchar red green blue -- the layout PCL
// (pcl::io::loadPLYFile), Open3D (read_point_cloud) and CloudCompare read natively -- and for
// triangle meshes. Written atomically (temp + rename). ASCII floats use FormatDouble17 of the
// float value.
#pragma once
#include <string>

#include "io/point_cloud.h"

namespace dynref {

enum class PlyFormat { kBinaryLittleEndian, kAscii };

void WritePly(const std::string& path, const PointCloud& cloud,
              PlyFormat format = PlyFormat::kBinaryLittleEndian,
              const std::string& comment = "");

// Reads back what WritePly writes (both formats; used by tests and `dynref` checks).
// Throws InputError for anything else.
PointCloud ReadPly(const std::string& path);

// binary_little_endian PLY: element vertex (float x y z), element face (list uchar uint
// vertex_indices) -- what MeshLab, CloudCompare, Open3D (read_triangle_mesh) and PCL read.
void WritePlyMesh(const std::string& path, const TriangleMesh& mesh, const std::string& comment = "");
// Reads back what WritePlyMesh writes; InputError naming the file otherwise (also for a face
// index outside the vertex list).
TriangleMesh ReadPlyMesh(const std::string& path);

}  // namespace dynref
