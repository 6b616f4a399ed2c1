#include "features/planes.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>
#include <stdexcept>

namespace dynref::features {

void PlaneOptions::Check() const {
  if (stride < 1) throw std::invalid_argument("stride must be >= 1");
  if (block < 2) throw std::invalid_argument("block must be >= 2");
  if (!(depth_sigma >= 0)) throw std::invalid_argument("depth_sigma must be >= 0");
  if (!(tol_init_m > 0) || !(tol_merge_m > 0)) throw std::invalid_argument("tol_init_m and tol_merge_m must be > 0");
  if (!(merge_angle_deg > 0 && merge_angle_deg <= 90)) throw std::invalid_argument("merge_angle_deg must be in (0, 90]");
  if (min_support < 3) throw std::invalid_argument("min_support must be >= 3");
  if (!(min_area_m2 >= 0)) throw std::invalid_argument("min_area_m2 must be >= 0");
  if (!(max_depth_m > 0)) throw std::invalid_argument("max_depth_m must be > 0");
  if (!(coplanar_angle_deg >= 0 && coplanar_angle_deg < 90)) throw std::invalid_argument("coplanar_angle_deg must be in [0, 90)");
  if (!(coplanar_dist_m >= 0)) throw std::invalid_argument("coplanar_dist_m must be >= 0");
  if (max_planes < 1) throw std::invalid_argument("max_planes must be >= 1");
}

bool FitPlane(const PlaneFitSums& f, Eigen::Vector3d* normal, double* d, double* mse) {
  if (f.n < 3) return false;
  const Eigen::Vector3d c = f.s / f.n;
  const Eigen::Matrix3d cov = f.ss / f.n - c * c.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  Eigen::Vector3d n = es.eigenvectors().col(0);  // eigenvalues ascending
  if (n.dot(c) > 0) n = -n;                     // towards the camera (origin)
  *normal = n;
  *d = -n.dot(c);
  *mse = std::max(0.0, es.eigenvalues()(0));
  return true;
}

namespace {

struct BlockNode {
  PlaneFitSums sums;
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  double d = 0, mse = 0;
  std::set<int> neighbours;  // node ids (ordered: deterministic scans)
  std::vector<int> blocks;   // block indices
  bool alive = false;
};

double SigmaZ(const PlaneOptions& o, double z) { return o.depth_sigma * z * z; }

// Organised cloud at grid resolution (invalid = z 0) and its block layout.
struct PlaneGrid {
  int gw = 0, gh = 0, bw = 0, bh = 0;
  std::vector<Eigen::Vector3d> P;
  const Eigen::Vector3d& at(int r, int c) const { return P[static_cast<size_t>(r) * gw + c]; }
};

PlaneGrid PlaneBackprojectGrid(const cv::Mat& depth_m, const Intrinsics& K, const PlaneOptions& o) {
  PlaneGrid g;
  g.gw = depth_m.cols / o.stride, g.gh = depth_m.rows / o.stride;
  g.P.assign(static_cast<size_t>(g.gw) * g.gh, Eigen::Vector3d::Zero());
  for (int r = 0; r < g.gh; ++r) {
    const float* row = depth_m.ptr<float>(r * o.stride);
    for (int c = 0; c < g.gw; ++c) {
      const double z = row[c * o.stride];
      if (z > 0 && z <= o.max_depth_m && std::isfinite(z))
        g.P[static_cast<size_t>(r) * g.gw + c] = K.Backproject(c * o.stride, r * o.stride, z);
    }
  }
  g.bw = g.gw / o.block, g.bh = g.gh / o.block;
  return g;
}

// A block becomes a node when all its points are valid, depth-continuous and planar.
bool PlaneFitBlock(const PlaneGrid& g, const PlaneOptions& o, int br, int bc, BlockNode* nd) {
  PlaneFitSums f;
  bool ok = true;
  for (int r = br * o.block; r < (br + 1) * o.block && ok; ++r)
    for (int c = bc * o.block; c < (bc + 1) * o.block && ok; ++c) {
      const Eigen::Vector3d& p = g.at(r, c);
      if (p.z() <= 0) { ok = false; break; }
      // Depth discontinuity to the right / below neighbour inside the block.
      const double tol = 4 * (SigmaZ(o, p.z()) + o.tol_init_m);
      if (c + 1 < (bc + 1) * o.block && (g.at(r, c + 1).z() <= 0 || std::fabs(g.at(r, c + 1).z() - p.z()) > tol)) ok = false;
      if (r + 1 < (br + 1) * o.block && (g.at(r + 1, c).z() <= 0 || std::fabs(g.at(r + 1, c).z() - p.z()) > tol)) ok = false;
      f.Add(p);
    }
  if (!ok) return false;
  nd->sums = f;
  if (!FitPlane(f, &nd->n, &nd->d, &nd->mse)) return false;
  const double z = f.s.z() / f.n;
  const double t = SigmaZ(o, z) + o.tol_init_m;
  if (nd->mse > t * t) return false;
  nd->alive = true;
  nd->blocks = {br * g.bw + bc};
  return true;
}

// 1. Blocks: one node per planar block, linked to its right / lower neighbour when the normals agree.
std::vector<BlockNode> PlaneBlockNodes(const PlaneGrid& g, const PlaneOptions& o, double cos_merge) {
  std::vector<BlockNode> nodes;
  std::vector<int> node_of_block(static_cast<size_t>(g.bw) * g.bh, -1);
  for (int br = 0; br < g.bh; ++br)
    for (int bc = 0; bc < g.bw; ++bc) {
      BlockNode nd;
      if (!PlaneFitBlock(g, o, br, bc, &nd)) continue;
      node_of_block[static_cast<size_t>(br) * g.bw + bc] = static_cast<int>(nodes.size());
      nodes.push_back(std::move(nd));
    }
  for (int br = 0; br < g.bh; ++br)
    for (int bc = 0; bc < g.bw; ++bc) {
      const int a = node_of_block[static_cast<size_t>(br) * g.bw + bc];
      if (a < 0) continue;
      const int right = bc + 1 < g.bw ? node_of_block[static_cast<size_t>(br) * g.bw + bc + 1] : -1;
      const int down = br + 1 < g.bh ? node_of_block[static_cast<size_t>(br + 1) * g.bw + bc] : -1;
      for (int b : {right, down})
        if (b >= 0 && nodes[a].n.dot(nodes[b].n) >= cos_merge) {
          nodes[a].neighbours.insert(b);
          nodes[b].neighbours.insert(a);
        }
    }
  return nodes;
}

struct PlaneMergeCandidate {
  int best = -1;
  PlaneFitSums sums;
  double mse = 0;
  Eigen::Vector3d n;
  double d = 0;
};

// The neighbour whose union with node a fits a plane with the smallest MSE.
PlaneMergeCandidate PlaneBestNeighbour(const std::vector<BlockNode>& nodes, int a, double cos_merge) {
  PlaneMergeCandidate best;
  for (int b : nodes[a].neighbours) {
    if (nodes[a].n.dot(nodes[b].n) < cos_merge) continue;
    PlaneFitSums u = nodes[a].sums;
    u.Add(nodes[b].sums);
    Eigen::Vector3d n;
    double d, mse;
    FitPlane(u, &n, &d, &mse);
    if (best.best < 0 || mse < best.mse) best.best = b, best.sums = u, best.mse = mse, best.n = n, best.d = d;
  }
  return best;
}

// Replaces nodes a and best by their union (a new node id) in the graph and the heap.
void PlaneMergeNodePair(std::vector<BlockNode>* nodes_p, std::set<std::pair<double, int>>* heap, int a,
                        const PlaneMergeCandidate& cand) {
  std::vector<BlockNode>& nodes = *nodes_p;
  const int best = cand.best;
  BlockNode m;
  m.sums = cand.sums, m.n = cand.n, m.d = cand.d, m.mse = cand.mse, m.alive = true;
  m.blocks = nodes[a].blocks;
  m.blocks.insert(m.blocks.end(), nodes[best].blocks.begin(), nodes[best].blocks.end());
  const int id = static_cast<int>(nodes.size());
  for (int x : {a, best}) {
    nodes[x].alive = false;
    for (int y : nodes[x].neighbours) {
      if (y == a || y == best) continue;
      nodes[y].neighbours.erase(x);
      nodes[y].neighbours.insert(id);
      m.neighbours.insert(y);
    }
  }
  heap->erase({nodes[best].mse, best});
  nodes.push_back(std::move(m));
  heap->insert({nodes[id].mse, id});
}

// 2. Agglomerative merging, smallest MSE first (ties: lower node id); returns the extracted node ids.
std::vector<int> PlaneMergeNodes(std::vector<BlockNode>* nodes_p, const PlaneOptions& o, double cos_merge) {
  std::vector<BlockNode>& nodes = *nodes_p;
  std::set<std::pair<double, int>> heap;
  for (int i = 0; i < static_cast<int>(nodes.size()); ++i) heap.insert({nodes[i].mse, i});
  std::vector<int> extracted;
  const double min_points = static_cast<double>(o.min_support) / (o.stride * o.stride);
  while (!heap.empty()) {
    const int a = heap.begin()->second;
    heap.erase(heap.begin());
    if (!nodes[a].alive) continue;
    const PlaneMergeCandidate cand = PlaneBestNeighbour(nodes, a, cos_merge);
    const double z = cand.best >= 0 ? cand.sums.s.z() / cand.sums.n : 0;
    const double t = SigmaZ(o, z) + o.tol_merge_m;
    if (cand.best >= 0 && cand.mse <= t * t) {
      PlaneMergeNodePair(&nodes, &heap, a, cand);
    } else {
      nodes[a].alive = false;
      for (int y : nodes[a].neighbours) nodes[y].neighbours.erase(a);
      if (nodes[a].sums.n >= min_points) extracted.push_back(a);
    }
  }
  return extracted;
}

// 3a. Grid points of each plane's blocks and of the blocks bordering them that lie within the
// tolerance join the closest such plane (PEAC assigns a boundary point to the nearest plane).
cv::Mat PlaneAssignGridLabels(const PlaneGrid& g, const PlaneOptions& o, const std::vector<BlockNode>& nodes,
                              const std::vector<int>& extracted) {
  cv::Mat grid_label(g.gh, g.gw, CV_16S, cv::Scalar(-1));
  cv::Mat grid_dist(g.gh, g.gw, CV_64F, cv::Scalar(std::numeric_limits<double>::infinity()));
  for (size_t k = 0; k < extracted.size(); ++k) {
    const BlockNode& nd = nodes[static_cast<size_t>(extracted[k])];
    std::set<int> blocks(nd.blocks.begin(), nd.blocks.end());
    for (int b : nd.blocks) {
      const int br = b / g.bw, bc = b % g.bw;
      if (bc > 0) blocks.insert(b - 1);
      if (bc + 1 < g.bw) blocks.insert(b + 1);
      if (br > 0) blocks.insert(b - g.bw);
      if (br + 1 < g.bh) blocks.insert(b + g.bw);
    }
    for (int b : blocks) {
      const int br = b / g.bw, bc = b % g.bw;
      for (int r = br * o.block; r < (br + 1) * o.block; ++r)
        for (int c = bc * o.block; c < (bc + 1) * o.block; ++c) {
          const Eigen::Vector3d& p = g.at(r, c);
          if (p.z() <= 0) continue;
          const double dist = std::fabs(nd.n.dot(p) + nd.d);
          if (dist > 3 * (SigmaZ(o, p.z()) + o.tol_init_m) || !(dist < grid_dist.at<double>(r, c))) continue;
          grid_dist.at<double>(r, c) = dist;  // strictly closer wins; ties keep the earlier plane
          grid_label.at<int16_t>(r, c) = static_cast<int16_t>(k);
        }
    }
  }
  return grid_label;
}

// 3b. Each plane's fit sums and metric area over the grid points labelled with it.
void PlaneRefitSums(const PlaneGrid& g, const Intrinsics& K, const PlaneOptions& o, const cv::Mat& grid_label,
                    std::vector<PlaneFitSums>* refit, std::vector<double>* area) {
  for (int r = 0; r < g.gh; ++r)
    for (int c = 0; c < g.gw; ++c) {
      const int k = grid_label.at<int16_t>(r, c);
      if (k < 0) continue;
      const Eigen::Vector3d& p = g.at(r, c);
      (*refit)[static_cast<size_t>(k)].Add(p);
      (*area)[static_cast<size_t>(k)] += p.z() * p.z() / (K.fx * K.fy) * o.stride * o.stride;
    }
}

// Coplanar patches (split by an occluder, or two faces of one wall) are one plane: merge
// pairs whose fitted normals and distances agree (spec 000 step 4 "merge neighbours with
// consistent parameters"), larger first; the absorbed plane's points take the larger's label.
// Returns merged_into (-1: not absorbed).
std::vector<int> PlaneMergeCoplanar(const PlaneOptions& o, std::vector<PlaneFitSums>* refit_p,
                                    std::vector<double>* area_p) {
  std::vector<PlaneFitSums>& refit = *refit_p;
  std::vector<double>& area = *area_p;
  const size_t count = refit.size();
  std::vector<int> merged_into(count, -1);
  std::vector<Eigen::Vector3d> n(count);
  std::vector<double> d(count, 0), mse(count, 0);
  std::vector<uint8_t> ok(count, 0);
  for (size_t k = 0; k < count; ++k) ok[k] = FitPlane(refit[k], &n[k], &d[k], &mse[k]);
  const double cos_coplanar = std::cos(o.coplanar_angle_deg * M_PI / 180.0);
  for (size_t a = 0; a < count; ++a) {
    if (!ok[a] || merged_into[a] >= 0) continue;
    for (size_t b = a + 1; b < count; ++b) {
      if (!ok[b] || merged_into[b] >= 0) continue;
      if (n[a].dot(n[b]) < cos_coplanar || std::fabs(d[a] - d[b]) > o.coplanar_dist_m) continue;
      const size_t big = refit[a].n >= refit[b].n ? a : b, small = big == a ? b : a;
      refit[big].Add(refit[small]);
      area[big] += area[small];
      refit[small] = PlaneFitSums{};
      area[small] = 0;
      merged_into[small] = static_cast<int>(big);
      FitPlane(refit[big], &n[big], &d[big], &mse[big]);
      if (big != a) break;  // a was absorbed
    }
  }
  return merged_into;
}

// Largest planes first, up to max_planes with enough area; returns the output label of each plane.
std::vector<int> PlaneSelectOutput(const PlaneOptions& o, const std::vector<PlaneFitSums>& refit,
                                   const std::vector<double>& area, const std::vector<int>& merged_into,
                                   std::vector<PlaneObservation>* planes) {
  std::vector<int> order(refit.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return refit[a].n > refit[b].n; });
  std::vector<int> new_label(refit.size(), -1);
  for (int k : order) {
    if (static_cast<int>(planes->size()) >= o.max_planes) break;
    if (merged_into[static_cast<size_t>(k)] >= 0 || area[k] < o.min_area_m2) continue;
    PlaneObservation pl;
    if (!FitPlane(refit[k], &pl.n, &pl.d, &pl.mse)) continue;
    pl.centroid = refit[k].s / refit[k].n;
    pl.points = static_cast<int>(refit[k].n);
    pl.area_m2 = area[k];
    new_label[k] = static_cast<int>(planes->size());
    planes->push_back(pl);
  }
  return new_label;
}

// Full-resolution labels: each pixel takes its grid cell's plane, followed through the merges.
void PlaneWriteLabels(const PlaneGrid& g, const PlaneOptions& o, const cv::Mat& grid_label,
                      const std::vector<int>& merged_into, const std::vector<int>& new_label, cv::Mat* labels) {
  for (int r = 0; r < labels->rows; ++r)
    for (int c = 0; c < labels->cols; ++c) {
      const int gr = r / o.stride, gc = c / o.stride;
      if (gr >= g.gh || gc >= g.gw) continue;
      int l = grid_label.at<int16_t>(gr, gc);
      while (l >= 0 && merged_into[static_cast<size_t>(l)] >= 0) l = merged_into[static_cast<size_t>(l)];
      if (l >= 0 && new_label[l] >= 0) labels->at<int16_t>(r, c) = static_cast<int16_t>(new_label[l]);
    }
}

}  // namespace

PlaneSegmentation SegmentPlanes(const cv::Mat& depth_m, const Intrinsics& K, const PlaneOptions& o) {
  o.Check();
  if (depth_m.type() != CV_32F) throw std::invalid_argument("SegmentPlanes needs a CV_32F depth image (metres)");
  PlaneSegmentation out;
  out.labels = cv::Mat(depth_m.size(), CV_16S, cv::Scalar(-1));
  const PlaneGrid g = PlaneBackprojectGrid(depth_m, K, o);
  const double cos_merge = std::cos(o.merge_angle_deg * M_PI / 180.0);
  std::vector<BlockNode> nodes = PlaneBlockNodes(g, o, cos_merge);
  const std::vector<int> extracted = PlaneMergeNodes(&nodes, o, cos_merge);
  // 3. Refinement at grid resolution: boundary points join the nearest plane, then each plane is
  // refitted on its points and coplanar planes are merged.
  const cv::Mat grid_label = PlaneAssignGridLabels(g, o, nodes, extracted);
  std::vector<PlaneFitSums> refit(extracted.size());
  std::vector<double> area(extracted.size(), 0.0);
  PlaneRefitSums(g, K, o, grid_label, &refit, &area);
  const std::vector<int> merged_into = PlaneMergeCoplanar(o, &refit, &area);
  const std::vector<int> new_label = PlaneSelectOutput(o, refit, area, merged_into, &out.planes);
  PlaneWriteLabels(g, o, grid_label, merged_into, new_label, &out.labels);
  return out;
}

}  // namespace dynref::features
