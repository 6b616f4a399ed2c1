// Verifiers of the sgdo records (ref/verify/README.md, section "SGDO-SLAM"). Written from
// seed 001 (spec 001) and ref/dynamic/sgdo/README.md "Trace"; never calls the stage code.
//   sgdo.mask      Sec. 3.2: instance in M iff class in dynamic_classes and conf >= min_confidence;
//                  (S): keypoint rejected iff its mask look-up names an instance of M.
//   sgdo.F         Sec. 3.3: F's inlier / usable counts, rank 2, validity.
//   sgdo.epipolar  Sec. 3.3 Eq. (5): D = |P2h^T F P1h| / sqrt(X^2 + Y^2), DS-SLAM pruning, RANSAC
//                  inlier test (symmetric distance <= threshold), D > th_epi.
//   sgdo.vote      spec 001 E1 (instance_vote): moving iff no paired point or dynamic >= ratio * paired.
//   sgdo.coarse    spec 001 E1: the combination of M and the epipolar test per keypoint.
//   sgdo.depth(.kf) Sec. 3.4 Eq. (8)-(9), Sec. 3.5: eps = (z_k - d_k) / d_k, |eps| > eta,
//                  omega = exp(-lambda eps^2).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <limits>
#include <set>

#include "io/coco_classes.h"
#include "verify/verifier.h"

namespace dynref::verify {
namespace {

using trace::Record;
using trace::RecordType;


// The last PROB of `stage` on `entity` in frame group `frame_pos` before record `before` (all of
// the frame when before = npos); nullptr if none.
const Record* ProbInFrame(const TraceModel& t, size_t frame_pos, const std::string& stage, const std::string& entity,
                          size_t before = std::string::npos) {
  const Record* found = nullptr;
  for (const RecordRef& ref : t.EntityRecords(entity)) {
    if (ref.frame_pos != frame_pos || ref.index >= before) continue;
    const Record& r = t.At(ref);
    if (r.type == RecordType::kProbability && r.stage == stage) found = &r;
  }
  return found;
}

std::optional<int64_t> CountInFrame(const TraceModel& t, size_t frame_pos, const std::string& stage,
                                    const std::string& name) {
  for (const Record& r : t.frames()[frame_pos].records)
    if (r.type == RecordType::kCount && r.stage == stage && r.name == name) return r.value;
  return std::nullopt;
}

std::string Param(const TraceModel& t, const std::string& stage, const std::string& key) {
  std::string v;
  t.StageParam(stage, key, &v);
  return v;
}

// Whether `value > th` when not within the tolerance of th: 1 yes, 0 no, -1 too close to tell
// (the stage's last bits decide; either recorded answer is accepted).
int Above(double value, double th) {
  if (Agrees(value, th, kTol)) return -1;
  return value > th ? 1 : 0;
}
void SameFlag(Check& c, const std::string& field, int expected, double recorded) {
  if (expected < 0) return;
  c.Near(field, expected, recorded, 0);
}

std::string FeatureEntity(int64_t frame, int64_t index) {
  return "f" + std::to_string(frame) + "." + std::to_string(index);
}
std::string InstanceEntity(int64_t frame, int64_t inst) {
  return "i" + std::to_string(frame) + "." + std::to_string(inst);
}

// Camera distortion (OpenCV k1 k2 p1 p2 k3) from the header's camera_json.
struct Distortion {
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
  bool any() const { return k1 != 0 || k2 != 0 || p1 != 0 || p2 != 0 || k3 != 0; }
};
Distortion ReadDistortion(const TraceModel& t) {
  Distortion d;
  const nlohmann::json c = nlohmann::json::parse(t.HeaderValue("camera_json"), nullptr, false);
  if (!c.is_object()) return d;
  d.k1 = c.value("k1", 0.0), d.k2 = c.value("k2", 0.0), d.p1 = c.value("p1", 0.0), d.p2 = c.value("p2", 0.0);
  d.k3 = c.value("k3", 0.0);
  return d;
}

// ---------------------------------------------------------------- sgdo.mask (Sec. 3.2)

// COCO ids of the config's sgdo.mask dynamic_classes (names or ids).
std::set<int> DynamicClassIds(const TraceModel& t) { return t.StageClassIds("sgdo.mask", "dynamic_classes"); }

// Whether instance `inst` of the frame is in M (its sgdo.mask instance record recomputed).
struct MaskInstance {
  bool recorded = false;
  bool dynamic = false;
  double class_id = 0, confidence = 0;
};
MaskInstance RecomputeMaskInstance(const TraceModel& t, const Record& r, Check& c) {
  MaskInstance m;
  m.recorded = true;
  m.class_id = c.Need(r, "class_id");
  m.confidence = c.Need(r, "confidence");
  const double min_conf = AppliedMinConfidence(t, r, "sgdo.mask", c);
  const std::set<int> classes = DynamicClassIds(t);
  if (classes.empty()) c.Missing("config sgdo.mask.dynamic_classes");
  m.dynamic = classes.count(static_cast<int>(m.class_id)) > 0 && m.confidence >= min_conf;
  return m;
}

void VerifyMaskProb(const TraceModel& t, RecordRef at, Check& c) {
  const Record& r = t.At(at);
  c.Near("before", 0, r.before, 0);
  if (r.kind == trace::EntityKind::kInstanceMask) {
    const MaskInstance m = RecomputeMaskInstance(t, r, c);
    c.Near("after", m.dynamic ? 1 : 0, r.after, 0);
    return;
  }
  // Feature of (S): the mask look-up must name 0 or an instance of M of this frame.
  const double inst = c.Need(r, "instance");
  if (!c.ok()) return;
  if (inst != 0) {
    const std::string id = InstanceEntity(t.frames()[at.frame_pos].frame, static_cast<int64_t>(inst));
    const Record* ir = ProbInFrame(t, at.frame_pos, "sgdo.mask", id);
    if (ir == nullptr) return c.Missing("sgdo.mask record of " + id);
    Check sub;
    const MaskInstance m = RecomputeMaskInstance(t, *ir, sub);
    if (!sub.ok()) return c.Missing("inputs of sgdo.mask " + id);
    c.Same("instance", std::string("an instance of M"), m.dynamic ? "an instance of M" : id + " (not in M)");
  }
  c.Near("after", inst != 0 ? 1 : 0, r.after, 0);
}

void VerifyMaskDecision(const TraceModel& t, RecordRef at, Check& c) {
  const Record& r = t.At(at);
  const Record* p = ProbInFrame(t, at.frame_pos, "sgdo.mask", r.entity, at.index);
  if (p == nullptr) return c.Missing("sgdo.mask PROB of " + r.entity);
  if (r.kind == trace::EntityKind::kInstanceMask) {
    const MaskInstance m = RecomputeMaskInstance(t, *p, c);
    if (!c.ok()) return;
    const double min_conf = AppliedMinConfidence(t, *p, "sgdo.mask", c);
    c.Same("kept", !m.dynamic, r.kept);
    c.Same("reason",
           m.dynamic ? "prior-dynamic:" + std::string(CocoClassName(static_cast<int>(m.class_id)))
                     : (m.confidence < min_conf ? "low-confidence" : "static-class"),
           r.reason);
    return;
  }
  const double inst = c.Need(*p, "instance");
  if (!c.ok()) return;
  c.Same("config sgdo.mask.reject_in_mask", std::string("true"), Param(t, "sgdo.mask", "reject_in_mask"));
  c.Same("kept", inst == 0, r.kept);
  c.Same("reason", std::string(inst == 0 ? "outside-mask" : "mask"), r.reason);
}

// ---------------------------------------------------------------- sgdo.coarse (Sec. 3.3)

// Prune codes of sgdo.epipolar (ref/dynamic/sgdo/README.md "Trace").
enum Prune { kUsable = 0, kLkFailed = 1, kBorder = 2, kPatchSad = 3, kInMask = 4, kNoPrevious = 5 };

struct FMatrix {
  Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
  bool valid = false;
};
bool ReadF(const TraceModel& t, size_t frame_pos, FMatrix* out, Check& c) {
  const std::string id = "f" + std::to_string(t.frames()[frame_pos].frame);
  const Record* r = ProbInFrame(t, frame_pos, "sgdo.F", id);
  if (r == nullptr) {
    c.Missing("sgdo.F record " + id);
    return false;
  }
  static const char* const kNames[9] = {"F00", "F01", "F02", "F10", "F11", "F12", "F20", "F21", "F22"};
  for (int k = 0; k < 9; ++k) out->F(k / 3, k % 3) = c.Need(*r, kNames[k]);
  out->valid = r->after == 1;
  return c.ok();
}

// Eq. (5): L2 = F P1h = (X, Y, Z); D = |P2h . L2| / sqrt(X^2 + Y^2) (+inf when X = Y = 0).
double PointLineDistance(const Eigen::Matrix3d& F, double u1, double v1, double u2, double v2) {
  const Eigen::Vector3d L = F * Eigen::Vector3d(u1, v1, 1.0);
  const double n = std::sqrt(L.x() * L.x() + L.y() * L.y());
  if (n == 0) return std::numeric_limits<double>::infinity();
  return std::abs(u2 * L.x() + v2 * L.y() + L.z()) / n;
}

void VerifyF(const TraceModel& t, RecordRef at, Check& c) {
  const Record& r = t.At(at);
  FMatrix F;
  if (!ReadF(t, at.frame_pos, &F, c)) return;
  const double usable = c.Need(r, "usable"), inliers = c.Need(r, "inliers");
  if (!c.ok()) return;
  int64_t used = 0, in = 0;
  for (const Record& e : t.frames()[at.frame_pos].records) {
    if (e.type != RecordType::kProbability || e.stage != "sgdo.epipolar") continue;
    used += Input(e, "used_for_F").value_or(0) == 1;
    in += Input(e, "F_inlier").value_or(0) == 1;
  }
  c.Near("before", 0, r.before, 0);
  c.Near("usable", static_cast<double>(used), usable, 0);
  c.Near("inliers", static_cast<double>(in), inliers, 0);
  // RANSAC keeps a model only when it has an inlier; fewer than 8 usable pairs: no model.
  c.Near("after", in > 0 ? 1 : 0, r.after, 0);
  if (r.after == 1) {
    c.Same("usable >= 8", true, usable >= 8);
    const double norm = F.F.norm();
    c.Near("det(F)/|F|^3 (rank 2)", 0, norm > 0 ? F.F.determinant() / (norm * norm * norm) : 1, kTol);
  } else {
    c.Near("|F| of no model", 0, F.F.norm(), 0);
  }
}

void VerifyEpipolar(const TraceModel& t, RecordRef at, Check& c) {
  const Record& r = t.At(at);
  const int64_t frame = t.frames()[at.frame_pos].frame;
  int64_t fr = 0, index = 0;
  if (!ParseDottedId(r.entity, "f", &fr, &index) || fr != frame) return c.Same("entity", FeatureEntity(frame, 0), r.entity);
  FMatrix F;
  if (!ReadF(t, at.frame_pos, &F, c)) return;
  const double u1 = c.Need(r, "u_prev"), v1 = c.Need(r, "v_prev"), u2 = c.Need(r, "u_cur"), v2 = c.Need(r, "v_cur");
  const double D = c.Need(r, "D_px"), th = c.Need(r, "th_epi_px"), inst = c.Need(r, "instance");
  const double used = c.Need(r, "used_for_F"), inlier = c.Need(r, "F_inlier"), sad = c.Need(r, "patch_sad");
  const double tracked = c.Need(r, "tracked"), F_valid = c.Need(r, "F_valid"), prune = c.Need(r, "prune");
  const double tested = c.Need(r, "tested");
  const double th_cfg = c.Need(t.StageNumber("sgdo.coarse", "th_epi_px"), "config sgdo.coarse.th_epi_px");
  const double border = c.Need(t.StageNumber("sgdo.coarse", "border_px"), "config sgdo.coarse.border_px");
  const double sad_max = c.Need(t.StageNumber("sgdo.coarse", "patch_sad_max"), "config sgdo.coarse.patch_sad_max");
  const double ransac_th =
      c.Need(t.StageNumber("sgdo.coarse", "ransac_threshold_px"), "config sgdo.coarse.ransac_threshold_px");
  const trace::Record* obs = t.Obs(at.frame_pos, index);
  if (obs == nullptr) c.Missing("OBS of " + r.entity);
  if (!t.camera().present) c.Missing("camera_json");
  if (!c.ok()) return;
  c.Near("before", 0, r.before, 0);
  c.Near("th_epi_px", th_cfg, th, 0);
  c.Near("F_valid", F.valid ? 1 : 0, F_valid, 0);
  // P2 is the keypoint (OBS holds the undistorted keypoint; F and D use undistorted pairs).
  const bool distorted = ReadDistortion(t).any();
  if (!distorted) {
    c.Near("u_cur", obs->u, u2, kTol);
    c.Near("v_cur", obs->v, v2, kTol);
  }
  // The keypoint's mask look-up: 0 or an instance of M (sgdo.mask record); none for (G).
  if (inst != 0) {
    if (Param(t, "sgdo.coarse", "combination") == "epipolar_only") {
      c.Near("instance (no mask in epipolar_only)", 0, inst, 0);
    } else {
      const std::string id = InstanceEntity(frame, static_cast<int64_t>(inst));
      const Record* ir = ProbInFrame(t, at.frame_pos, "sgdo.mask", id);
      if (ir == nullptr) return c.Missing("sgdo.mask record of " + id);
      c.Near("instance in M (sgdo.mask " + id + " after)", 1, ir->after, 0);
    }
  }
  // DS-SLAM pruning (spec 001 step 3b): LK failure, border (truncated positions, raw pixels),
  // 3x3 SAD > c_patch, P2 in M; code 5 = no previous frame.
  int expected_prune;
  if (tracked == 0) {
    expected_prune = prune == kNoPrevious ? kNoPrevious : kLkFailed;
  } else {
    const int W = t.camera().width, H = t.camera().height, b = static_cast<int>(border);
    auto near_border = [&](double u, double v) {
      const int x = static_cast<int>(u), y = static_cast<int>(v);
      return x < b || x >= W - b || y < b || y >= H - b;
    };
    const bool at_border = near_border(u1, v1) || near_border(u2, v2);
    if (at_border && !distorted) expected_prune = kBorder;
    else if (prune == kBorder && distorted) expected_prune = kBorder;  // raw positions not in the trace
    else if (sad > sad_max) expected_prune = kPatchSad;
    else expected_prune = inst != 0 ? kInMask : kUsable;
    if (expected_prune == kBorder) c.Near("patch_sad (not computed at the border)", 0, sad, 0);
  }
  c.Near("prune", expected_prune, prune, 0);
  if (prune == kNoPrevious) {
    const Record* fr_rec = ProbInFrame(t, at.frame_pos, "sgdo.F", "f" + std::to_string(frame));
    c.Near("sgdo.F usable (no previous frame)", 0, Input(*fr_rec, "usable").value_or(-1), 0);
  }
  const bool usable = tracked == 1 && expected_prune == kUsable;
  c.Near("used_for_F", usable ? 1 : 0, used, 0);
  // RANSAC inlier: max of the two one-sided distances <= threshold.
  if (usable && F.valid) {
    const double sym = std::max(PointLineDistance(F.F, u1, v1, u2, v2), PointLineDistance(F.F.transpose(), u2, v2, u1, v1));
    SameFlag(c, "F_inlier", Above(sym, ransac_th) < 0 ? -1 : (sym <= ransac_th ? 1 : 0), inlier);
  } else {
    c.Near("F_inlier", 0, inlier, 0);
  }
  const bool test = tracked == 1 && expected_prune != kBorder && expected_prune != kPatchSad && F.valid;
  c.Near("tested", test ? 1 : 0, tested, 0);
  if (!test) {
    c.Near("D_px", 0, D, 0);
    c.Near("after", 0.5, r.after, 0);
    return;
  }
  const double D_expected = PointLineDistance(F.F, u1, v1, u2, v2);
  c.Near("D_px", D_expected, D, kTol);
  SameFlag(c, "after", Above(D_expected, th_cfg), r.after);
}

// The sgdo.epipolar facts the combination reads, from the record (verified on its own).
struct EpiFacts {
  bool tested = false, dynamic = false, tracked = false, flow_pruned = false, F_valid = false;
  int64_t instance = 0;
  std::string no_distance;
};
bool ReadEpi(const Record& r, EpiFacts* e, Check& c) {
  const double tested = c.Need(r, "tested"), D = c.Need(r, "D_px"), th = c.Need(r, "th_epi_px");
  const double tracked = c.Need(r, "tracked"), prune = c.Need(r, "prune"), F_valid = c.Need(r, "F_valid");
  const double inst = c.Need(r, "instance");
  if (!c.ok()) return false;
  e->tested = tested == 1;
  e->dynamic = e->tested && D > th;
  e->tracked = tracked == 1;
  e->flow_pruned = prune == kBorder || prune == kPatchSad;
  e->F_valid = F_valid == 1;
  e->instance = static_cast<int64_t>(inst);
  e->no_distance = !e->tracked ? "no-pair" : e->flow_pruned ? "pruned" : !e->F_valid ? "no-F" : "";
  return true;
}

// A moving instance under instance_vote: paired = tested points of the instance, dynamic = those
// with D > th_epi; moving iff paired == 0 or dynamic >= vote_ratio * paired.
void VerifyVote(const TraceModel& t, RecordRef at, Check& c) {
  const Record& r = t.At(at);
  int64_t frame = 0, inst = 0;
  if (!ParseDottedId(r.entity, "i", &frame, &inst)) return c.Same("entity", std::string("i<frame>.<inst>"), r.entity);
  const double dynamic = c.Need(r, "dynamic"), paired = c.Need(r, "paired"), ratio = c.Need(r, "vote_ratio");
  const double ratio_cfg = c.Need(t.StageNumber("sgdo.coarse", "vote_ratio"), "config sgdo.coarse.vote_ratio");
  if (!c.ok()) return;
  int64_t n_dyn = 0, n_pair = 0;
  for (const Record& e : t.frames()[at.frame_pos].records) {
    if (e.type != RecordType::kProbability || e.stage != "sgdo.epipolar") continue;
    EpiFacts f;
    Check sub;
    if (!ReadEpi(e, &f, sub)) return c.Missing("inputs of sgdo.epipolar " + e.entity);
    if (f.instance != inst || !f.tested) continue;
    ++n_pair;
    n_dyn += f.dynamic;
  }
  c.Near("before", 0, r.before, 0);
  c.Near("vote_ratio", ratio_cfg, ratio, 0);
  c.Near("paired", static_cast<double>(n_pair), paired, 0);
  c.Near("dynamic", static_cast<double>(n_dyn), dynamic, 0);
  const bool moving = n_pair == 0 || static_cast<double>(n_dyn) >= ratio_cfg * static_cast<double>(n_pair);
  c.Near("after", moving ? 1 : 0, r.after, 0);
}

void VerifyCoarseDecision(const TraceModel& t, RecordRef at, Check& c) {
  const Record& r = t.At(at);
  const Record* p = ProbInFrame(t, at.frame_pos, "sgdo.epipolar", r.entity, at.index);
  if (p == nullptr) return c.Missing("sgdo.epipolar record of " + r.entity);
  EpiFacts e;
  if (!ReadEpi(*p, &e, c)) return;
  const std::string mode = Param(t, "sgdo.coarse", "combination");
  const bool in_mask = e.instance != 0;
  bool keep = true;
  std::string reason;
  auto per_point = [&] {
    if (e.dynamic) keep = false, reason = "epipolar";
    else keep = true, reason = e.tested ? "static" : e.no_distance;
  };
  if (mode == "epipolar_only") {
    per_point();
  } else if (mode == "per_point") {
    if (e.dynamic) keep = false, reason = "epipolar";
    else if (in_mask && !e.tested) keep = false, reason = "mask-" + e.no_distance;
    else keep = true, reason = e.tested ? "static" : e.no_distance;
  } else if (mode == "instance_vote") {
    if (in_mask) {
      const std::string id = InstanceEntity(t.frames()[at.frame_pos].frame, e.instance);
      const Record* v = ProbInFrame(t, at.frame_pos, "sgdo.vote", id);
      if (v == nullptr) return c.Missing("sgdo.vote record of " + id);
      keep = v->after != 1;
      reason = keep ? "instance-still" : "instance-vote";
    } else {
      per_point();
    }
  } else {
    return c.Missing("config sgdo.coarse.combination (per_point|instance_vote|epipolar_only), got '" + mode + "'");
  }
  c.Same("kept", keep, r.kept);
  c.Same("reason", reason, r.reason);
}

// ---------------------------------------------------------------- sgdo.depth (Sec. 3.4-3.5)

// The keyframe pose carrier: a rigid T_kw, and the keyframe the stage counted as reference.
void VerifyDepthKf(const TraceModel& t, RecordRef at, Check& c) {
  const Record& r = t.At(at);
  int64_t kf = 0;
  if (!ParseNumberId(r.entity, "kf", &kf)) return c.Same("entity", std::string("kf<id>"), r.entity);
  Eigen::Matrix3d R;
  for (int k = 0; k < 12; ++k) {
    const double v = c.Need(r, "T_kw[" + std::to_string(k) + "]");
    if (k % 4 < 3) R(k / 4, k % 4) = v;
  }
  const std::optional<int64_t> ref = CountInFrame(t, at.frame_pos, "sgdo.depth", "reference_kf");
  if (!ref) c.Missing("COUNT sgdo.depth reference_kf");
  if (!c.ok()) return;
  c.Near("kf (COUNT sgdo.depth reference_kf)", static_cast<double>(*ref), static_cast<double>(kf), 0);
  c.Near("before", 0, r.before, 0);
  c.Near("after", 0, r.after, 0);
  const Eigen::Matrix3d E = R * R.transpose() - Eigen::Matrix3d::Identity();
  c.Near("R R^T - I (T_kw rigid)", 0, E.cwiseAbs().maxCoeff(), kTol);
  c.Near("det R", 1, R.determinant(), kTol);
}

// The last `weight` a PROB record gave the feature earlier in this frame (1 if none).
double PreviousWeight(const TraceModel& t, RecordRef at, const std::string& entity) {
  double w = 1.0;
  for (const RecordRef& ref : t.EntityRecords(entity)) {
    if (ref.frame_pos != at.frame_pos || ref.index >= at.index) continue;
    const Record& e = t.At(ref);
    if (e.type != RecordType::kProbability) continue;
    if (const std::optional<double> v = Input(e, "weight")) w = *v;
  }
  return w;
}

struct DepthOutcome {
  bool tested = false;
  std::string skip;  // why untested
  bool reject = false;
};

// Eq. (8)-(9) for one feature record; reports the recomputed fields through c.
DepthOutcome RecomputeDepth(const TraceModel& t, RecordRef at, Check& c) {
  DepthOutcome out;
  const Record& r = t.At(at);
  const int64_t frame = t.frames()[at.frame_pos].frame;
  int64_t fr = 0, index = 0;
  if (!ParseDottedId(r.entity, "f", &fr, &index) || fr != frame) {
    c.Same("entity", FeatureEntity(frame, 0), r.entity);
    return out;
  }
  const double kf = c.Need(r, "kf"), d_i = c.Need(r, "depth_i_m"), u_k = c.Need(r, "u_k"), v_k = c.Need(r, "v_k");
  const double z_k = c.Need(r, "z_k"), d_k = c.Need(r, "d_k"), eps = c.Need(r, "eps"), eta = c.Need(r, "eta");
  const double lambda = c.Need(r, "lambda"), tested = c.Need(r, "tested"), omega = c.Need(r, "omega");
  const double weight = c.Need(r, "weight");
  const double eta_cfg = c.Need(t.StageNumber("sgdo.depth", "eta"), "config sgdo.depth.eta");
  const double lambda_cfg = c.Need(t.StageNumber("sgdo.depth", "lambda"), "config sgdo.depth.lambda");
  const double reject_on = c.Need(t.StageNumber("sgdo.depth", "reject"), "config sgdo.depth.reject");
  const double weight_on = c.Need(t.StageNumber("sgdo.depth", "weight"), "config sgdo.depth.weight");
  const Record* obs = t.Obs(at.frame_pos, index);
  if (obs == nullptr) c.Missing("OBS of " + r.entity);
  const std::string kf_id = "kf" + std::to_string(static_cast<int64_t>(kf));
  const Record* carrier = c.ok() ? ProbInFrame(t, at.frame_pos, "sgdo.depth.kf", kf_id, at.index) : nullptr;
  if (c.ok() && carrier == nullptr) c.Missing("sgdo.depth.kf record of " + kf_id);
  const Record* pose = nullptr;
  for (const Record& e : t.frames()[at.frame_pos].records)
    if (e.type == RecordType::kPose && e.name == "initial") pose = &e;
  if (pose == nullptr) c.Missing("POSE initial of frame " + std::to_string(frame));
  const CameraModel& cam = t.camera();
  if (!cam.present) c.Missing("camera_json");
  if (!c.ok()) return out;
  Eigen::Matrix4d T_kw = Eigen::Matrix4d::Identity(), T_wc = Eigen::Matrix4d::Identity();
  for (int k = 0; k < 12; ++k) {
    T_kw(k / 4, k % 4) = c.Need(*carrier, "T_kw[" + std::to_string(k) + "]");
    T_wc(k / 4, k % 4) = pose->T_wc[static_cast<size_t>(k)];
  }
  if (!c.ok()) return out;
  c.Near("eta", eta_cfg, eta, 0);
  c.Near("lambda", lambda_cfg, lambda, 0);
  // The feature's depth is its OBS depth (OBS writes 0 for none).
  if (obs->depth_m > 0) c.Near("depth_i_m (OBS depth_m)", obs->depth_m, d_i, 0);
  else c.Same("depth_i_m (no OBS depth)", true, !(d_i > 0) || !std::isfinite(d_i));
  // Eq. (8): P_c = d_i K^-1 [u v 1]^T; X_k = T_kw T_wc P_c (T_kc = T_kw T_cw^-1).
  const double u = obs->u, v = obs->v;
  out.skip = "";
  double zk = 0, uk = 0, vk = 0, dk = 0, e = 0;
  if (!(d_i > 0) || !std::isfinite(d_i)) {
    out.skip = "no-depth";
  } else {
    const Eigen::Vector4d P_c(d_i * (u - cam.cx) / cam.fx, d_i * (v - cam.cy) / cam.fy, d_i, 1.0);
    const Eigen::Vector4d X_k = T_kw * (T_wc * P_c);
    zk = X_k.z();
    if (!(zk > 0)) {
      out.skip = "behind-kf";
    } else {
      // Eq. (9) with K restored (spec 001 E5); nearest pixel of the (distorted) raw depth image.
      uk = cam.fx * X_k.x() / zk + cam.cx;
      vk = cam.fy * X_k.y() / zk + cam.cy;
      const Distortion dist = ReadDistortion(t);
      double ru = uk, rv = vk;
      if (dist.any()) {  // OpenCV's forward Brown-Conrady model
        const double x = (uk - cam.cx) / cam.fx, y = (vk - cam.cy) / cam.fy, r2 = x * x + y * y;
        const double radial = 1 + dist.k1 * r2 + dist.k2 * r2 * r2 + dist.k3 * r2 * r2 * r2;
        ru = cam.fx * (x * radial + 2 * dist.p1 * x * y + dist.p2 * (r2 + 2 * x * x)) + cam.cx;
        rv = cam.fy * (y * radial + dist.p1 * (r2 + 2 * y * y) + 2 * dist.p2 * x * y) + cam.cy;
      }
      const long x = std::lround(ru), y = std::lround(rv);
      if (x < 0 || y < 0 || x >= cam.width || y >= cam.height) {
        out.skip = "outside-kf";
      } else {
        dk = d_k;  // the keyframe depth map's value: pixel data, an input
        if (!(dk > 0) || !std::isfinite(dk)) out.skip = "kf-no-depth";
        else e = (zk - dk) / dk;  // Eq. (8)-(9): eps
      }
    }
  }
  out.tested = out.skip.empty();
  c.Near("z_k", zk, z_k, kTol);
  c.Near("u_k", uk, u_k, kTol);
  c.Near("v_k", vk, v_k, kTol);
  if (out.skip != "kf-no-depth") c.Near("d_k", dk, d_k, 0);
  c.Near("tested", out.tested ? 1 : 0, tested, 0);
  c.Near("eps", e, eps, kTol);
  // Sec. 3.5: omega = exp(-lambda eps^2), 1 when untested; reject iff |eps| > eta.
  const double w = out.tested ? std::exp(-lambda_cfg * e * e) : 1.0;
  c.Near("omega", w, omega, kTol);
  const int above = out.tested ? Above(std::abs(e), eta_cfg) : 0;
  const bool reject = reject_on == 1 && above == 1;
  out.reject = reject_on == 1 && (above == 1 || (above < 0 && r.after == 1));
  const double prev = PreviousWeight(t, at, r.entity);
  c.Near("weight", weight_on == 1 && !out.reject ? w : prev, weight, kTol);
  c.Near("before", 1.0 - prev, r.before, kTol);
  if (reject_on == 1 && above < 0) return out;  // too close to eta to tell: either answer
  c.Near("after", reject ? 1.0 : 1.0 - (weight_on == 1 ? w : prev), r.after, kTol);
  return out;
}

void VerifyDepthProb(const TraceModel& t, RecordRef at, Check& c) {
  if (t.At(at).kind == trace::EntityKind::kKeyFrame) return VerifyDepthKf(t, at, c);
  RecomputeDepth(t, at, c);
}

void VerifyDepthDecision(const TraceModel& t, RecordRef at, Check& c) {
  const Record& r = t.At(at);
  const Record* p = ProbInFrame(t, at.frame_pos, "sgdo.depth", r.entity, at.index);
  if (p == nullptr) return c.Missing("sgdo.depth PROB of " + r.entity);
  // Recompute the PROB (its own verdict is its record's; here only the outcome is needed).
  RecordRef pref = at;
  for (const RecordRef& ref : t.EntityRecords(r.entity))
    if (&t.At(ref) == p) pref = ref;
  Check sub;
  const DepthOutcome o = RecomputeDepth(t, pref, sub);
  if (sub.verdict().status == Status::kUnverifiable) return c.Missing(sub.verdict().field);
  c.Same("kept", !o.reject, r.kept);
  c.Same("reason", o.reject ? std::string("depth-eps") : o.tested ? std::string("consistent") : "untested:" + o.skip,
         r.reason);
}

}  // namespace

void AddSgdoVerifiers(VerifierList& out) {
  auto add = [&](RecordType type, const char* stage, StageVerifier::Fn fn) {
    out.push_back(std::make_unique<StageVerifier>(type, stage, std::move(fn)));
  };
  add(RecordType::kProbability, "sgdo.mask", VerifyMaskProb);
  add(RecordType::kDecision, "sgdo.mask", VerifyMaskDecision);
  add(RecordType::kProbability, "sgdo.F", VerifyF);
  add(RecordType::kProbability, "sgdo.epipolar", VerifyEpipolar);
  add(RecordType::kProbability, "sgdo.vote", VerifyVote);
  add(RecordType::kDecision, "sgdo.coarse", VerifyCoarseDecision);
  add(RecordType::kProbability, "sgdo.depth", VerifyDepthProb);
  add(RecordType::kProbability, "sgdo.depth.kf", VerifyDepthKf);
  add(RecordType::kDecision, "sgdo.depth", VerifyDepthDecision);
}

}  // namespace dynref::verify
