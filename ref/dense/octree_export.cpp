#include "dense/octree_export.h"

#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>

#include "core/atomic_file.h"

namespace dynref::dense {

OctreeStats WriteOctrees(const PointCloud& cloud, double resolution_m, const std::string& ot_path,
                         const std::string& bt_path) {
  octomap::ColorOcTree color(resolution_m);
  octomap::OcTree occupancy(resolution_m);
  for (const ColoredPoint& p : cloud) {  // input order: the result is deterministic
    const octomap::point3d q(p.x, p.y, p.z);
    color.updateNode(q, true);
    color.integrateNodeColor(q.x(), q.y(), q.z(), p.r, p.g, p.b);
    occupancy.updateNode(q, true);
  }
  color.updateInnerOccupancy();
  occupancy.updateInnerOccupancy();
  {
    AtomicOutputFile out(ot_path, true);
    if (!color.write(out.stream())) throw std::runtime_error("cannot write " + ot_path);
    out.Commit();
  }
  {
    AtomicOutputFile out(bt_path, true);
    if (!occupancy.writeBinary(out.stream())) throw std::runtime_error("cannot write " + bt_path);
    out.Commit();
  }
  OctreeStats s;
  s.leaf_nodes = color.getNumLeafNodes();
  s.inner_nodes = color.calcNumNodes() - s.leaf_nodes;
  for (auto it = color.begin_leafs(); it != color.end_leafs(); ++it) s.occupied_leaves += color.isNodeOccupied(*it);
  s.depth = color.getTreeDepth();
  return s;
}

}  // namespace dynref::dense
