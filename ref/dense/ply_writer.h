// PLY writer for coloured point clouds: "ply / format binary_little_endian 1.0" (or ascii),
// one element "vertex" with float x y z and uchar red green blue -- the layout PCL
// (pcl::io::loadPLYFile), Open3D (read_point_cloud) and CloudCompare read natively.
// Written atomically (temp + rename). ASCII floats use FormatDouble17 of the float value.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dense/point_cloud.h"

namespace dynref::dense {

enum class PlyFormat { kBinaryLittleEndian, kAscii };

void WritePly(const std::string& path, const PointCloud& cloud,
              PlyFormat format = PlyFormat::kBinaryLittleEndian,
              const std::string& comment = "");

// Reads back what WritePly writes (both formats; used by tests and `dynref` checks).
// Throws InputError for anything else.
PointCloud ReadPly(const std::string& path);

// A triangle mesh (e.g. the static scene of a synthetic sequence, gt/static_scene.ply).
struct TriangleMesh {
  std::vector<std::array<float, 3>> vertices;
  std::vector<std::array<uint32_t, 3>> faces;  // vertex indices, counter-clockwise seen from outside
};

// binary_little_endian PLY: element vertex (float x y z), element face (list uchar uint
// vertex_indices) -- what MeshLab, CloudCompare, Open3D (read_triangle_mesh) and PCL read.
void WritePlyMesh(const std::string& path, const TriangleMesh& mesh, const std::string& comment = "");
// Reads back what WritePlyMesh writes; InputError naming the file otherwise (also for a face
// index outside the vertex list).
TriangleMesh ReadPlyMesh(const std::string& path);

}  // namespace dynref::dense
