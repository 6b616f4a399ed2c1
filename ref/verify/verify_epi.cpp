// Verifiers of the enhanced-epipolar records (seed 004, ref/dynamic/epi/README.md "Trace") and of
// the backbone MNN2 match records (ref/trace/README.md "Backbone MNN2 matches"); ref/verify/
// README.md "Enhanced-epipolar SLAM" lists each formula, its inputs and tolerance. Written from
// spec 004 (Sec. 3.1 enhancement, Sec. 3.2 MNN2, Sec. 3.3.1 epipolar vote, Sec. 3.3.2 DLT gates)
// and ORB-SLAM2's rotation histogram; never calls the stage code.
#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "verify/verifier.h"

namespace dynref::verify {
namespace {

using trace::EntityKind;
using trace::Record;
using trace::RecordType;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Tolerance of the DLT point and its depths / reprojection errors (epi.nerf): the null vector of
// the 4 x 4 DLT system is recomputed by another SVD; its conditioning grows as 1 / parallax.
constexpr double kDltTol = 1e-7;

bool IsProb(const Record& r, const char* stage) { return r.type == RecordType::kProbability && r.stage == stage; }

void ZeroP(const Record& r, Check& c) {
  c.Near("before", 0, r.before, 0);
  c.Near("after", 0, r.after, 0);
}

// The first record of stage `stage` on `entity` in frame group `pos`, before index `before`.
const Record* FindInGroup(const TraceModel& t, size_t pos, size_t before, RecordType type, const std::string& stage,
                          const std::string& entity) {
  const std::vector<Record>& recs = t.frames()[pos].records;
  for (size_t i = 0; i < before && i < recs.size(); ++i)
    if (recs[i].type == type && recs[i].stage == stage && recs[i].entity == entity) return &recs[i];
  return nullptr;
}

// The last epi.nerf keyframe record of kf<id> (any frame group).
const Record* NerfKeyframe(const TraceModel& t, int64_t id) {
  const Record* out = nullptr;
  for (const RecordRef& ref : t.EntityRecords("kf" + std::to_string(id)))
    if (IsProb(t.At(ref), "epi.nerf")) out = &t.At(ref);
  return out;
}

// Camera distortion from the header (camera_json k1 k2 p1 p2 k3): with none, undistorted pixels
// are the OBS pixels.
bool CameraHasDistortion(const TraceModel& t) {
  const std::string text = t.HeaderValue("camera_json");
  if (text.empty()) return true;
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_object()) return true;
  for (const char* k : {"k1", "k2", "p1", "p2", "k3"})
    if (j.value(k, 0.0) != 0.0) return true;
  return false;
}

// R (inputs R00..R22) and t (t0..t2) of a record; false (and Missing) when absent.
bool ReadPose(const Record& r, Check& c, Eigen::Matrix3d* R, Eigen::Vector3d* t) {
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) (*R)(i, k) = c.Need(r, "R" + std::to_string(i) + std::to_string(k));
    (*t)(i) = c.Need(r, "t" + std::to_string(i));
  }
  return c.verdict().status != Status::kUnverifiable;
}

void CheckRotation(const Eigen::Matrix3d& R, Check& c) {
  const Eigen::Matrix3d e = R.transpose() * R - Eigen::Matrix3d::Identity();
  c.Near("R^T R - I", 0, e.cwiseAbs().maxCoeff(), 1e-9);
  c.Near("det R", 1, R.determinant(), 1e-9);
}

// ---------------------------------------------------------------------------------------------
// epi.enhance (spec 004 step 1a, 1d): the CDF percentile rule and the fitness.
class EnhanceVerifier : public Verifier {
 public:
  bool Claims(const Record& r) const override { return IsProb(r, "epi.enhance"); }
  void Verify(const TraceModel& t, RecordRef at, Check& c) const override {
    const Record& r = t.At(at);
    ZeroP(r, c);
    const double s = c.Need(t.StageNumber("epi.enhance", "s"), "config epi.enhance.s");
    const double lo = c.Need(r, "I_lo"), hi = c.Need(r, "I_hi");
    const double lo_below = c.Need(r, "cdf_lo_below"), cdf_lo = c.Need(r, "cdf_lo");
    const double hi_below = c.Need(r, "cdf_hi_below"), cdf_hi = c.Need(r, "cdf_hi");
    const double alpha = c.Need(r, "alpha"), p = c.Need(r, "p");
    const double sum = c.Need(r, "sobel_sum"), edges = c.Need(r, "edge_pixels"), pixels = c.Need(r, "pixels");
    const double entropy = c.Need(r, "entropy"), fitness = c.Need(r, "fitness");
    if (!c.ok()) return;
    // a. I_lo = min{g : CDF(g) >= s}: CDF(I_lo - 1) < s <= CDF(I_lo); likewise I_hi with 1 - s.
    c.Near("I_lo * 255 (a grey level)", std::round(lo * 255), lo * 255);
    c.Near("I_hi * 255 (a grey level)", std::round(hi * 255), hi * 255);
    c.Same("I_lo: CDF(I_lo - 1) < s <= CDF(I_lo)", true, lo_below < s && s <= cdf_lo);
    c.Same("I_hi: CDF(I_hi - 1) < 1 - s <= CDF(I_hi)", true, hi_below < 1.0 - s && 1.0 - s <= cdf_hi);
    if (std::round(lo * 255) == 0) c.Near("cdf_lo_below (I_lo = 0)", 0, lo_below, 0);
    if (std::round(hi * 255) == 0) c.Near("cdf_hi_below (I_hi = 0)", 0, hi_below, 0);
    c.Same("I_lo <= I_hi", true, lo <= hi);
    if (t.camera().present) c.Near("pixels", double(t.camera().width) * t.camera().height, pixels, 0);
    // d. fit = ln(ln(sum |Sobel|)) * n_edge / (H W) * entropy(E); -inf without edges.
    const double expected = !(sum > std::exp(1.0)) || edges == 0
                                ? -kInf
                                : std::log(std::log(sum)) * (edges / pixels) * entropy;
    c.Near("fitness", expected, fitness);
    // alpha, p: fixed by the config, or the BOA result of the first frame.
    const double optimise = c.Need(t.StageNumber("epi.enhance", "optimise"), "config epi.enhance.optimise");
    if (std::isnan(optimise)) return;
    if (optimise == 0) {
      c.Near("alpha", c.Need(t.StageNumber("epi.enhance", "alpha"), "config epi.enhance.alpha"), alpha);
      c.Near("p", c.Need(t.StageNumber("epi.enhance", "p"), "config epi.enhance.p"), p);
      return;
    }
    const Record* boa = nullptr;
    size_t boa_pos = 0;
    for (size_t pos = 0; pos <= at.frame_pos && boa == nullptr; ++pos)
      for (const Record& b : t.frames()[pos].records)
        if (IsProb(b, "epi.boa") && Input(b, "alpha")) boa = &b, boa_pos = pos;
    if (boa == nullptr) return c.Missing("the epi.boa result record (optimise: true)");
    c.Near("alpha (epi.boa)", c.Need(*boa, "alpha"), alpha, 0);
    c.Near("p (epi.boa)", c.Need(*boa, "p"), p, 0);
    // The BOA's best fitness is the fitness of E(I_s) on its frame with the chosen (alpha, p).
    if (boa_pos == at.frame_pos) c.Near("fitness (epi.boa best_fitness)", c.Need(*boa, "best_fitness"), fitness);
  }
};

// epi.boa (spec 004 E2, BOA with greedy replacement): the best fitness never decreases, one
// record per iteration, evaluations = population x (iterations + 1), (alpha, p) in the box.
class BoaVerifier : public Verifier {
 public:
  bool Claims(const Record& r) const override { return IsProb(r, "epi.boa"); }
  void Verify(const TraceModel& t, RecordRef at, Check& c) const override {
    const Record& r = t.At(at);
    ZeroP(r, c);
    const double iterations = c.Need(t.StageNumber("epi.enhance", "boa_iterations"), "config boa_iterations");
    const double population = c.Need(t.StageNumber("epi.enhance", "boa_population"), "config boa_population");
    const double best = c.Need(r, "best_fitness");
    if (!c.ok()) return;
    // The earlier iteration records of this entity in this frame group.
    const std::vector<Record>& recs = t.frames()[at.frame_pos].records;
    std::vector<double> earlier;
    for (size_t i = 0; i < at.index; ++i)
      if (IsProb(recs[i], "epi.boa") && recs[i].entity == r.entity && Input(recs[i], "iteration"))
        earlier.push_back(Input(recs[i], "best_fitness").value_or(kNaN));
    if (const std::optional<double> it = Input(r, "iteration")) {
      c.Near("iteration", double(earlier.size()), *it, 0);
      c.Same("iteration < boa_iterations", true, *it < iterations);
      if (!earlier.empty()) c.Same("best_fitness >= previous iteration's", true, best >= earlier.back());
      return;
    }
    const double alpha = c.Need(r, "alpha"), p = c.Need(r, "p"), evaluations = c.Need(r, "evaluations");
    const double alpha_max = c.Need(t.StageNumber("epi.enhance", "alpha_max"), "config alpha_max");
    const double p_min = c.Need(t.StageNumber("epi.enhance", "p_min"), "config p_min");
    const double p_max = c.Need(t.StageNumber("epi.enhance", "p_max"), "config p_max");
    if (!c.ok()) return;
    c.Near("iteration records", iterations, double(earlier.size()), 0);
    if (!earlier.empty()) c.Near("best_fitness (last iteration)", earlier.back(), best, 0);
    c.Near("evaluations", population * (iterations + 1), evaluations, 0);
    c.Same("alpha in [0, alpha_max]", true, alpha >= 0 && alpha <= alpha_max);
    c.Same("p in [p_min, p_max]", true, p >= p_min && p <= p_max);
  }
};

// epi.pose (spec 004 step 5b, E8): a pose iff inliers >= min_inliers; R a rotation.
class PoseVerifier : public Verifier {
 public:
  bool Claims(const Record& r) const override { return IsProb(r, "epi.pose"); }
  void Verify(const TraceModel& t, RecordRef at, Check& c) const override {
    const Record& r = t.At(at);
    ZeroP(r, c);
    const double pairs = c.Need(r, "static_pairs"), inliers = c.Need(r, "inliers");
    const double min_inliers = c.Need(r, "min_inliers"), pose = c.Need(r, "pose");
    const double config_min = c.Need(t.StageNumber("epi.vote", "pose_min_inliers"), "config pose_min_inliers");
    Eigen::Matrix3d R;
    Eigen::Vector3d tr;
    if (!ReadPose(r, c, &R, &tr) || !c.ok()) return;
    c.Near("min_inliers", config_min, min_inliers, 0);
    c.Same("pose (inliers >= min_inliers)", inliers >= min_inliers, pose == 1);
    c.Same("inliers <= static_pairs", true, inliers <= pairs);
    if (pose == 1) return CheckRotation(R, c);
    c.Near("inliers (no pose)", 0, inliers, 0);
    c.Near("|R| + |t| (no pose)", 0, R.cwiseAbs().sum() + tr.cwiseAbs().sum(), 0);
  }
};

// The epipolar distance of Eq. (14) with F = K^-T [t]x R K^-1 (Eq. (12)); t = 0 (no F): the
// distance to H p_prev, H = K R K^-1, the point the line tends to; a zero line otherwise: NaN.
double EpipolarDistancePx(const CameraModel& cam, const Eigen::Matrix3d& R, const Eigen::Vector3d& t, double u0,
                          double v0, double u1, double v1) {
  Eigen::Matrix3d K, K_inv;
  K << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1;
  K_inv << 1 / cam.fx, 0, -cam.cx / cam.fx, 0, 1 / cam.fy, -cam.cy / cam.fy, 0, 0, 1;
  if (t.x() == 0 && t.y() == 0 && t.z() == 0) {
    const Eigen::Vector3d h = K * R * K_inv * Eigen::Vector3d(u0, v0, 1);
    return std::hypot(u1 - h.x() / h.z(), v1 - h.y() / h.z());
  }
  Eigen::Matrix3d tx;
  tx << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
  const Eigen::Matrix3d F = K_inv.transpose() * tx * R * K_inv;
  const Eigen::Vector3d l = F * Eigen::Vector3d(u0, v0, 1);  // l = F p_(k-1) = (A, B, C)
  const double norm = std::hypot(l.x(), l.y());
  if (norm == 0) return kNaN;
  return std::abs(l.x() * u1 + l.y() * v1 + l.z()) / norm;
}

// epi.epipolar (spec 004 step 5c): the distance from the pair and the frame's epi.pose, the
// violation D > eps.
class EpipolarVerifier : public Verifier {
 public:
  bool Claims(const Record& r) const override { return IsProb(r, "epi.epipolar"); }
  void Verify(const TraceModel& t, RecordRef at, Check& c) const override {
    const Record& r = t.At(at);
    c.Near("before", 0, r.before, 0);
    const double eps = c.Need(r, "eps_px"), d = c.Need(r, "distance_px");
    const double instance = c.Need(r, "instance"), tracked = c.Need(r, "tracked"), pose = c.Need(r, "pose");
    const double config_eps = c.Need(t.StageNumber("epi.vote", "epi_threshold_px"), "config epi_threshold_px");
    if (!c.ok()) return;
    c.Near("eps_px", config_eps, eps, 0);
    c.Same("instance > 0", true, instance > 0);
    int64_t frame = -1, index = -1;
    if (!ParseDottedId(r.entity, "f", &frame, &index) || frame != r.frame)
      return c.Same("entity", "f" + std::to_string(r.frame) + ".<index>", r.entity);
    const Record* pr = FindInGroup(t, at.frame_pos, at.index, RecordType::kProbability, "epi.pose",
                                   "f" + std::to_string(r.frame));
    if (pr == nullptr) return c.Missing("epi.pose record of f" + std::to_string(r.frame));
    c.Near("pose (epi.pose)", c.Need(*pr, "pose"), pose, 0);
    double expected = kNaN;
    if (tracked == 1 && pose == 1) {
      if (!t.camera().present) return c.Missing("header camera_json");
      const double u0 = c.Need(r, "u_prev"), v0 = c.Need(r, "v_prev"), u1 = c.Need(r, "u_cur"), v1 = c.Need(r, "v_cur");
      Eigen::Matrix3d R;
      Eigen::Vector3d tr;
      if (!ReadPose(*pr, c, &R, &tr) || !c.ok()) return;
      // The current pixel is the keypoint (undistorted pixels = OBS pixels without distortion).
      const size_t pos = at.frame_pos;
      if (!CameraHasDistortion(t)) {
        const Record* obs = t.Obs(pos, index);
        if (obs == nullptr) return c.Missing("OBS of " + r.entity);
        c.Near("u_cur (OBS u)", obs->u, u1);
        c.Near("v_cur (OBS v)", obs->v, v1);
      }
      expected = EpipolarDistancePx(t.camera(), R, tr, u0, v0, u1, v1);
    }
    c.Near("distance_px", expected, d);
    c.Near("after (D > eps)", d > eps ? 1.0 : 0.0, r.after, 0);
  }
};

// epi.vote PROB (spec 004 step 5d, E8): the mask's votes counted from the frame's epi.epipolar
// records; dynamic iff no matched keypoint or violating / matched > vote_ratio.
struct VoteCount {
  int matched = 0, violating = 0;
};
VoteCount CountVotes(const TraceModel& t, size_t pos, double instance, double eps) {
  VoteCount v;
  for (const Record& e : t.frames()[pos].records) {
    if (!IsProb(e, "epi.epipolar") || Input(e, "instance").value_or(-1) != instance) continue;
    const double d = Input(e, "distance_px").value_or(kNaN);
    if (std::isnan(d)) continue;
    ++v.matched;
    v.violating += d > eps;
  }
  return v;
}

class VoteVerifier : public Verifier {
 public:
  bool Claims(const Record& r) const override { return IsProb(r, "epi.vote"); }
  void Verify(const TraceModel& t, RecordRef at, Check& c) const override {
    const Record& r = t.At(at);
    c.Near("before", 0, r.before, 0);
    int64_t frame = -1, inst = -1;
    if (!ParseDottedId(r.entity, "i", &frame, &inst) || frame != r.frame)
      return c.Same("entity", "i" + std::to_string(r.frame) + ".<inst>", r.entity);
    const double matched = c.Need(r, "matched"), violating = c.Need(r, "violating"), ratio = c.Need(r, "ratio");
    const double vote_ratio = c.Need(r, "vote_ratio");
    const double config_ratio = c.Need(t.StageNumber("epi.vote", "vote_ratio"), "config vote_ratio");
    const double eps = c.Need(t.StageNumber("epi.vote", "epi_threshold_px"), "config epi_threshold_px");
    if (!c.ok()) return;
    c.Near("vote_ratio", config_ratio, vote_ratio, 0);
    const VoteCount v = CountVotes(t, at.frame_pos, double(inst), eps);
    c.Near("matched (epi.epipolar records with a distance)", v.matched, matched, 0);
    c.Near("violating (D > eps)", v.violating, violating, 0);
    const double expected_ratio = v.matched > 0 ? double(v.violating) / v.matched : 0.0;
    c.Near("ratio", expected_ratio, ratio);
    const bool dynamic = v.matched == 0 || expected_ratio > config_ratio;
    c.Near("after (mask dynamic)", dynamic ? 1.0 : 0.0, r.after, 0);
  }
};

// epi.vote DECISIONs: a mask's (kept = not dynamic, reason) and a feature's exclusion (its
// instance, from its epi.epipolar record, was voted dynamic).
class VoteDecisionVerifier : public Verifier {
 public:
  bool Claims(const Record& r) const override { return r.type == RecordType::kDecision && r.stage == "epi.vote"; }
  void Verify(const TraceModel& t, RecordRef at, Check& c) const override {
    const Record& r = t.At(at);
    if (r.kind == EntityKind::kInstanceMask) {
      const Record* p = FindInGroup(t, at.frame_pos, at.index, RecordType::kProbability, "epi.vote", r.entity);
      if (p == nullptr) return c.Missing("epi.vote PROB of " + r.entity);
      const double matched = c.Need(*p, "matched"), ratio = c.Need(*p, "ratio");
      const double vote_ratio = c.Need(t.StageNumber("epi.vote", "vote_ratio"), "config vote_ratio");
      if (!c.ok()) return;
      const bool dynamic = matched == 0 || ratio > vote_ratio;
      c.Same("kept", !dynamic, r.kept);
      c.Same("reason", matched == 0 ? "no-matched-keypoint" : (dynamic ? "vote>ratio" : "vote<=ratio"), r.reason);
      return;
    }
    if (r.kind != EntityKind::kFeature) return c.Same("kind", "instance_mask or feature", "other");
    c.Same("kept", false, r.kept);
    c.Same("reason", "dynamic-mask", r.reason);
    const Record* e = FindInGroup(t, at.frame_pos, at.index, RecordType::kProbability, "epi.epipolar", r.entity);
    if (e == nullptr) return c.Missing("epi.epipolar record of " + r.entity + " (its instance)");
    const double inst = c.Need(*e, "instance");
    if (!c.ok()) return;
    const std::string iid = "i" + std::to_string(r.frame) + "." + std::to_string(int64_t(inst));
    const Record* v = FindInGroup(t, at.frame_pos, at.index, RecordType::kDecision, "epi.vote", iid);
    if (v == nullptr) return c.Missing("epi.vote decision of " + iid);
    c.Same("instance " + iid + " voted dynamic", true, !v->kept);
  }
};

// ---------------------------------------------------------------------------------------------
// MNN2 (spec 004 step 3, Eq. (4)-(7)): accept row i's nearest column j1 iff d1 < tau,
// d1 < rho d2 and i is j1's nearest row; outcome = the first failing test (1 tau, 2 ratio,
// 3 not mutual); then 4 = ORB-SLAM2's rotation histogram (tracking), 5 = the epipole / epipolar
// line test (triangulation search).
int Mnn2RuleOutcome(const Record& r, double rho, Check& c) {
  const double d1 = c.Need(r, "distance"), d2 = c.Need(r, "second"), tau = c.Need(r, "tau");
  const double i = c.Need(r, "kf_feature"), rev = c.Need(r, "reverse_kf_feature");
  if (!(d1 < tau)) return 1;
  if (!(d1 < rho * d2)) return 2;
  if (rev != i) return 3;
  return 0;
}

// ORB-SLAM2 ORBmatcher: bin of the keypoint angle difference (its factor 1 / HISTO_LENGTH, kept).
int RotationBinOf(float kf_angle, float angle) {
  float rot = kf_angle - angle;
  if (rot < 0.0f) rot += 360.0f;
  int bin = static_cast<int>(std::round(rot * (1.0f / 30)));
  return bin == 30 ? 0 : bin;
}

class Mnn2Verifier : public Verifier {
 public:
  bool Claims(const Record& r) const override {
    return r.type == RecordType::kProbability &&
           (r.stage == "match.mnn2.reference" || r.stage == "match.mnn2.relocalisation" ||
            r.stage == "match.mnn2.triangulation");
  }
  void Verify(const TraceModel& t, RecordRef at, Check& c) const override {
    const Record& r = t.At(at);
    ZeroP(r, c);
    const bool tri = r.stage == "match.mnn2.triangulation";
    const double rho = c.Need(r, "rho"), config_rho = c.Need(t.BackboneNumber("mnn2_ratio"), "config mnn2_ratio");
    const double d1 = c.Need(r, "distance"), d2 = c.Need(r, "second"), ratio = c.Need(r, "ratio");
    const double i = c.Need(r, "kf_feature"), rev = c.Need(r, "reverse_kf_feature");
    const double rev_d = c.Need(r, "reverse_distance"), outcome = c.Need(r, "outcome");
    c.Need(r, "kf");
    if (!c.ok()) return;
    c.Near("rho", config_rho, rho, 0);
    c.Near("ratio", d2 > 0 ? d1 / d2 : 0.0, ratio);
    c.Same("distance <= second", true, d1 <= d2);
    // The reverse nearest row of column j1 is at most as far as row i (the same row: as far).
    c.Same("reverse_distance <= distance", true, rev_d <= d1);
    if (rev == i) c.Near("reverse_distance (row i)", d1, rev_d, 0);
    int expected = Mnn2RuleOutcome(r, rho, c);
    if (!c.ok()) return;
    if (expected == 0 && tri) {
      const double e2 = c.Need(r, "epipole_d2"), eg = c.Need(r, "epipole_gate");
      const double l2 = c.Need(r, "line_d2"), lg = c.Need(r, "line_gate");
      if (!c.ok()) return;
      // ORB-SLAM2 SearchForTriangulation: too close to the epipole (both monocular), then
      // CheckDistEpipolarLine d^2 < 3.84 sigma^2.
      if ((!std::isnan(e2) && e2 < eg) || !(l2 < lg)) expected = 5;
    } else if (expected == 0) {
      if (c.Need(r, "rotation_check") == 1 && !InTopBins(t, at, r, rho, c)) expected = 4;
    } else if (tri) {
      c.Same("geometric inputs NaN (not reached)", true,
             std::isnan(Input(r, "line_d2").value_or(0)) && std::isnan(Input(r, "epipole_d2").value_or(0)));
    }
    if (!c.ok()) return;
    c.Near("outcome", expected, outcome, 0);
  }

 private:
  // Whether r's rotation bin is one of the three fullest of its call (contiguous records of the
  // same stage and keyframe in this frame group), counting the rows the MNN2 rule accepts;
  // ORB-SLAM2 ComputeThreeMaxima (second / third dropped below 10 % of the first).
  static bool InTopBins(const TraceModel& t, RecordRef at, const Record& r, double rho, Check& c) {
    const std::vector<Record>& recs = t.frames()[at.frame_pos].records;
    const double kf = *Input(r, "kf");
    auto same_call = [&](const Record& o) {
      return o.type == RecordType::kProbability && o.stage == r.stage && Input(o, "kf").value_or(-1) == kf;
    };
    size_t first = at.index, last = at.index;
    while (first > 0 && same_call(recs[first - 1])) --first;
    while (last + 1 < recs.size() && same_call(recs[last + 1])) ++last;
    std::vector<int> hist(30, 0);
    for (size_t k = first; k <= last; ++k) {
      Check sub;
      if (Mnn2RuleOutcome(recs[k], rho, sub) != 0 || !sub.ok()) continue;
      const double a = sub.Need(recs[k], "kf_angle"), b = sub.Need(recs[k], "angle");
      if (!sub.ok()) {
        c.Missing("kf_angle / angle of a record of the call");
        return true;
      }
      ++hist[size_t(RotationBinOf(float(a), float(b)))];
    }
    int max1 = 0, max2 = 0, max3 = 0, ind1 = -1, ind2 = -1, ind3 = -1;
    for (int b = 0; b < 30; ++b) {
      const int s = hist[size_t(b)];
      if (s > max1) {
        max3 = max2, ind3 = ind2, max2 = max1, ind2 = ind1, max1 = s, ind1 = b;
      } else if (s > max2) {
        max3 = max2, ind3 = ind2, max2 = s, ind2 = b;
      } else if (s > max3) {
        max3 = s, ind3 = b;
      }
    }
    if (max2 < 0.1f * float(max1)) ind2 = ind3 = -1;
    else if (max3 < 0.1f * float(max1)) ind3 = -1;
    const int bin = RotationBinOf(float(*Input(r, "kf_angle")), float(*Input(r, "angle")));
    return bin == ind1 || bin == ind2 || bin == ind3;
  }
};

// ---------------------------------------------------------------------------------------------
// epi.nerf (spec 004 step 7, Sec. 3.3.2): per exported keyframe its final pose; per MNN2 match
// the DLT point and the gates (0 ok, 1 parallax, 2 behind, 3 reprojection, 4 degenerate).
class NerfVerifier : public Verifier {
 public:
  bool Claims(const Record& r) const override { return IsProb(r, "epi.nerf"); }
  void Verify(const TraceModel& t, RecordRef at, Check& c) const override {
    const Record& r = t.At(at);
    ZeroP(r, c);
    if (r.kind == EntityKind::kKeyFrame) return VerifyKeyframe(t, at, r, c);
    const double kf = c.Need(r, "kf"), ref_kf = c.Need(r, "ref_kf");
    const double d1 = c.Need(r, "distance"), d2 = c.Need(r, "second"), rho = c.Need(r, "rho"), tau = c.Need(r, "tau");
    const double config_rho = c.Need(t.StageNumber("epi.nerf", "mnn_ratio"), "config epi.nerf.mnn_ratio");
    const double cos_max = c.Need(t.StageNumber("epi.nerf", "parallax_cos_max"), "config parallax_cos_max");
    const double gate = c.Need(t.StageNumber("epi.nerf", "reprojection_px"), "config reprojection_px");
    const Eigen::Vector2d x0(c.Need(r, "u"), c.Need(r, "v")), x1(c.Need(r, "ref_u"), c.Need(r, "ref_v"));
    const double outcome = c.Need(r, "outcome");
    if (!c.ok()) return;
    if (!t.camera().present) return c.Missing("header camera_json");
    // The match: MNN2 accepted it (mutual implied: only accepted matches are traced).
    c.Near("rho", config_rho, rho, 0);
    c.Same("distance < tau", true, d1 < tau);
    c.Same("distance < rho * second", true, d1 < rho * d2);
    const Record* k0 = NerfKeyframe(t, int64_t(kf));
    const Record* k1 = NerfKeyframe(t, int64_t(ref_kf));
    if (k0 == nullptr || k1 == nullptr) return c.Missing("epi.nerf keyframe records kf" + std::to_string(int64_t(kf)) +
                                                         " / kf" + std::to_string(int64_t(ref_kf)));
    c.Near("ref_kf (keyframe record)", c.Need(*k0, "ref_kf"), ref_kf, 0);
    Eigen::Matrix3d R0, R1;
    Eigen::Vector3d t0, t1;
    if (!ReadPose(*k0, c, &R0, &t0) || !ReadPose(*k1, c, &R1, &t1)) return;
    // The pixels are the keypoints (OBS of the keyframe's frame) when the camera has no distortion.
    if (!CameraHasDistortion(t)) {
      int64_t frame = -1, index = -1;
      if (!ParseDottedId(r.entity, "f", &frame, &index)) return c.Same("entity", "f<frame>.<index>", r.entity);
      c.Near("frame (keyframe record)", c.Need(*k0, "frame"), double(frame), 0);
      const std::optional<size_t> pos = t.FramePos(frame);
      const Record* obs = pos ? t.Obs(*pos, index) : nullptr;
      if (obs == nullptr) return c.Missing("OBS of " + r.entity);
      c.Near("u (OBS)", obs->u, x0.x());
      c.Near("v (OBS)", obs->v, x0.y());
    }
    const CameraModel& cam = t.camera();
    Eigen::Matrix3d K;
    K << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1;
    // Parallax of the world-frame rays R^T K^-1 x.
    auto ray = [&](const Eigen::Matrix3d& R, const Eigen::Vector2d& x) {
      return Eigen::Vector3d(R.transpose() * Eigen::Vector3d((x.x() - cam.cx) / cam.fx, (x.y() - cam.cy) / cam.fy, 1));
    };
    const Eigen::Vector3d a = ray(R0, x0), b = ray(R1, x1);
    const double cos_parallax = a.dot(b) / (a.norm() * b.norm());
    c.Near("cos_parallax", cos_parallax, c.Need(r, "cos_parallax"));
    int expected = 0;
    Eigen::Vector3d X = Eigen::Vector3d::Constant(kNaN);
    double z0 = kNaN, z1 = kNaN, e0 = kNaN, e1 = kNaN;
    if (cos_parallax >= cos_max) {
      expected = 1;
    } else {
      // DLT: rows u P3 - P1, v P3 - P2 of both views; X = the right singular vector of the
      // smallest singular value, dehomogenised.
      Eigen::Matrix<double, 3, 4> P0, P1;
      P0 << R0, t0;
      P1 << R1, t1;
      P0 = K * P0;
      P1 = K * P1;
      Eigen::Matrix4d A;
      A << x0.x() * P0.row(2) - P0.row(0), x0.y() * P0.row(2) - P0.row(1), x1.x() * P1.row(2) - P1.row(0),
          x1.y() * P1.row(2) - P1.row(1);
      const Eigen::Vector4d h = Eigen::JacobiSVD<Eigen::Matrix4d>(A, Eigen::ComputeFullV).matrixV().col(3);
      if (h(3) == 0) {
        expected = 4;
      } else {
        X = h.head<3>() / h(3);
        const Eigen::Vector3d c0 = R0 * X + t0, c1 = R1 * X + t1;
        z0 = c0.z(), z1 = c1.z();
        if (!(z0 > 0) || !(z1 > 0)) {
          expected = 2;
        } else {
          auto err = [&](const Eigen::Vector3d& p, const Eigen::Vector2d& x) {
            return std::hypot(cam.fx * p.x() / p.z() + cam.cx - x.x(), cam.fy * p.y() / p.z() + cam.cy - x.y());
          };
          e0 = err(c0, x0), e1 = err(c1, x1);
          if (!(e0 < gate) || !(e1 < gate)) expected = 3;
        }
      }
    }
    c.Near("X", X.x(), c.Need(r, "X"), kDltTol);
    c.Near("Y", X.y(), c.Need(r, "Y"), kDltTol);
    c.Near("Z", X.z(), c.Need(r, "Z"), kDltTol);
    c.Near("z", z0, c.Need(r, "z"), kDltTol);
    c.Near("ref_z", z1, c.Need(r, "ref_z"), kDltTol);
    c.Near("err_px", e0, c.Need(r, "err_px"), kDltTol);
    c.Near("ref_err_px", e1, c.Need(r, "ref_err_px"), kDltTol);
    c.Near("outcome", expected, outcome, 0);
  }

 private:
  static void VerifyKeyframe(const TraceModel& t, RecordRef at, const Record& r, Check& c) {
    Eigen::Matrix3d R;
    Eigen::Vector3d tr;
    const double ref = c.Need(r, "ref_kf");
    c.Need(r, "frame");
    if (!ReadPose(r, c, &R, &tr) || !c.ok()) return;
    CheckRotation(R, c);
    // ref_kf = the previous exported keyframe (the record before, in file order; -1 for the first).
    double previous = -1;
    for (size_t pos = 0; pos <= at.frame_pos; ++pos) {
      const std::vector<Record>& recs = t.frames()[pos].records;
      const size_t end = pos == at.frame_pos ? at.index : recs.size();
      for (size_t i = 0; i < end; ++i) {
        int64_t id = -1;
        if (IsProb(recs[i], "epi.nerf") && recs[i].kind == EntityKind::kKeyFrame && ParseNumberId(recs[i].entity, "kf", &id))
          previous = double(id);
      }
    }
    c.Near("ref_kf (previous exported keyframe)", previous, ref, 0);
  }
};

}  // namespace

void AddEpiVerifiers(VerifierList& out) {
  out.push_back(std::make_unique<EnhanceVerifier>());
  out.push_back(std::make_unique<BoaVerifier>());
  out.push_back(std::make_unique<PoseVerifier>());
  out.push_back(std::make_unique<EpipolarVerifier>());
  out.push_back(std::make_unique<VoteVerifier>());
  out.push_back(std::make_unique<VoteDecisionVerifier>());
  out.push_back(std::make_unique<Mnn2Verifier>());
  out.push_back(std::make_unique<NerfVerifier>());
}

}  // namespace dynref::verify
