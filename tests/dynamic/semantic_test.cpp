// Semantic mapping (seed 002): the interaction test against hand-counted pairs, and the map
// files loading back in the libraries users open them with (OctoMap, a map_server YAML/PGM
// parser, PCD/PLY readers); floor fit on a planted floor.
#include <catch2/catch.hpp>
#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>
#include <yaml-cpp/yaml.h>

#include <fstream>
#include <sstream>

#include <Eigen/Geometry>

#include "dense/occupancy_grid.h"
#include "dense/octree_export.h"
#include "dense/pcd_io.h"
#include "dynamic/semantic/interaction.h"
#include "test_support.h"

using namespace dynref;

TEST_CASE("semantic interaction: pairs within d_max across the boundary, mean |dz| against T_int") {
  // A = person column x = 10, rows 0..4; B = chair column x = 13, rows 0..4. With d_max = 6 a
  // pixel a = (10, y) pairs with b = (13, y') iff 9 + (y - y')^2 <= 36, i.e. |y - y'| <= 5: all 5
  // rows, so |Q| = 25.
  cv::Mat ids = cv::Mat::zeros(20, 30, CV_16U);
  ids(cv::Rect(10, 0, 1, 5)).setTo(1);
  ids(cv::Rect(13, 0, 1, 5)).setTo(2);
  cv::Mat depth(20, 30, CV_32F, cv::Scalar(2.0f));
  depth(cv::Rect(13, 0, 1, 5)).setTo(2.1f);  // chair 10 cm behind the person: contact
  const auto bounds = semantic::InstanceBounds(ids);
  const semantic::InteractionResult r = semantic::TestInteraction(ids, depth, bounds, 1, 2, 6, 0.3);
  CHECK(r.pairs == 25);
  CHECK(r.dz_mean_m == Approx(0.1).epsilon(1e-6));
  CHECK(r.interacting);
  // d_max = 2: the columns are 3 px apart, no pair, no verdict.
  CHECK(semantic::TestInteraction(ids, depth, bounds, 1, 2, 2, 0.3).pairs == 0);
  CHECK_FALSE(semantic::TestInteraction(ids, depth, bounds, 1, 2, 2, 0.3).interacting);
  // Chair 1 m behind (occlusion, not contact): mean dz 1.0 >= T_int.
  depth(cv::Rect(13, 0, 1, 5)).setTo(3.0f);
  const semantic::InteractionResult far = semantic::TestInteraction(ids, depth, bounds, 1, 2, 6, 0.3);
  CHECK(far.pairs == 25);
  CHECK(far.dz_mean_m == Approx(1.0));
  CHECK_FALSE(far.interacting);
  // Invalid depth pixels form no pairs: 2 of the 5 chair pixels without depth -> 5 x 3 pairs.
  depth(cv::Rect(13, 0, 1, 2)).setTo(0.0f);
  CHECK(semantic::TestInteraction(ids, depth, bounds, 1, 2, 6, 0.3).pairs == 15);
}

TEST_CASE("semantic map files: PCD round trip, OctoMap .ot/.bt load back, map_server YAML + PGM parse") {
  const std::string dir = test::ScratchDir("semantic_files");
  dense::PointCloud cloud;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) {
      dense::ColoredPoint p;
      // A patch 0.5 m above the floor, one point in the middle of each 10 cm cell.
      p.x = 0.1f * i + 0.05f, p.y = -0.5f, p.z = 1.0f + 0.1f * j + 0.05f;
      p.r = uint8_t(10 * i), p.g = uint8_t(20 * j), p.b = 7;
      cloud.push_back(p);
    }
  dense::WritePcd(dir + "/c.pcd", cloud);
  const dense::PointCloud back = dense::ReadPcd(dir + "/c.pcd");
  REQUIRE(back.size() == cloud.size());
  CHECK(back[37].x == cloud[37].x);
  CHECK(back[37].g == cloud[37].g);

  const dense::OctreeStats os = dense::WriteOctrees(cloud, 0.05, dir + "/m.ot", dir + "/m.bt");
  CHECK(os.occupied_leaves == 100);  // 10 cm spacing > 5 cm leaves: one leaf per point
  octomap::AbstractOcTree* tree = octomap::AbstractOcTree::read(dir + "/m.ot");
  REQUIRE(tree != nullptr);
  auto* color = dynamic_cast<octomap::ColorOcTree*>(tree);
  REQUIRE(color != nullptr);
  CHECK(color->getNumLeafNodes() == os.leaf_nodes);
  const octomap::ColorOcTreeNode* n = color->search(cloud[34].x, cloud[34].y, cloud[34].z);  // i = 3, j = 4
  REQUIRE(n != nullptr);
  CHECK(color->isNodeOccupied(n));
  CHECK(int(n->getColor().r) == 30);
  CHECK(int(n->getColor().g) == 80);
  delete tree;
  octomap::OcTree occ(0.1);
  REQUIRE(occ.readBinary(dir + "/m.bt"));
  CHECK(occ.getResolution() == Approx(0.05));
  CHECK(occ.getNumLeafNodes() > 0);

  // Floor: y points down in the world (first camera); the patch is 0.5 m above a floor at y = 0.
  dense::FloorPlane floor;
  floor.found = true;
  floor.n = Eigen::Vector3d(0, -1, 0);
  floor.d = 0;
  dense::GridOptions go;
  go.cell_m = 0.1;
  const dense::OccupancyGrid g = dense::BuildOccupancyGrid(cloud, floor, go);
  CHECK(g.points_used == 100);
  CHECK(g.width * g.height == 100);
  CHECK(g.occupied_cells == 100);
  dense::WriteMapServer(g, dir + "/grid.pgm", dir + "/grid.yaml");
  const YAML::Node y = YAML::LoadFile(dir + "/grid.yaml");
  CHECK(y["image"].as<std::string>() == "grid.pgm");
  CHECK(y["resolution"].as<double>() == Approx(0.1));
  CHECK(y["origin"].size() == 3);
  CHECK(y["occupied_thresh"].as<double>() == Approx(0.65));
  std::ifstream pgm(dir + "/grid.pgm", std::ios::binary);
  std::string magic;
  int w = 0, h = 0, maxval = 0;
  pgm >> magic >> w >> h >> maxval;
  pgm.get();
  CHECK(magic == "P5");
  CHECK(w == g.width);
  CHECK(h == g.height);
  CHECK(maxval == 255);
  std::string pixels((std::istreambuf_iterator<char>(pgm)), std::istreambuf_iterator<char>());
  REQUIRE(pixels.size() == size_t(w * h));
  CHECK(std::count(pixels.begin(), pixels.end(), char(0)) == 100);  // every cell occupied
}

TEST_CASE("semantic floor fit: a planted tilted floor is recovered under clutter") {
  dense::PointCloud cloud;
  // Floor 1 m below the camera, tilted 20 degrees about x (camera pitched down): points with
  // n . p + d = 0 for n = R(-y); boxes of clutter above it.
  const double a = 20 * M_PI / 180;
  const Eigen::Vector3d n(0, -std::cos(a), -std::sin(a));
  const double d = 1.0;
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 60; ++j) {
      const Eigen::Vector3d u(1, 0, 0), v = n.cross(u).normalized();
      const Eigen::Vector3d p = -d * n + (i * 0.05 - 1.5) * u + (j * 0.05) * v;
      cloud.push_back({float(p.x()), float(p.y()), float(p.z())});
    }
  const Eigen::Vector3d u(1, 0, 0), v = n.cross(u).normalized();
  for (int k = 0; k < 1500; ++k) {  // clutter 0.2-1.2 m above the floor, over its middle
    const Eigen::Vector3d p = -d * n + (0.2 + 0.001 * (k % 1000)) * n + (0.001 * k - 0.75) * u + 1.5 * v;
    cloud.push_back({float(p.x()), float(p.y()), float(p.z())});
  }
  const dense::FloorPlane f = dense::FitFloor(cloud, dense::FloorOptions{});
  REQUIRE(f.found);
  CHECK(f.n.dot(n) > std::cos(1 * M_PI / 180));
  CHECK(f.d == Approx(d).margin(0.01));
}

