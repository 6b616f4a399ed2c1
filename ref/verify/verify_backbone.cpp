// Verifiers of the backbone records (ref/verify/README.md, "Backbone"): every RESIDUAL of the
// pose-only optimisation ("track.pose#N") and local BA ("localba#N"), their link records
// ("track.pose.obs", "localba.obs"), the keyframe records ("track.keyframe") and the structure
// geometry records ("structure"). Written from ORB-SLAM2's Optimizer (Mur-Artal & Tardos 2017,
// Sec. IV-B; g2o EdgeSE3ProjectXYZ / EdgeStereoSE3ProjectXYZ, RobustKernelHuber), seed 000
// Sec. 3.6 (lines, planes) and ref/trace/README.md; never calls the optimiser.
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include "verify/verifier.h"

namespace dynref::verify {
namespace {

using trace::Record;
using trace::RecordType;

// inv_sigma2 of an octave: the backbone's pyramid is float32 (ORB-SLAM2 mvInvLevelSigma2), the
// verifier's 1 / scale^(2 o) double: up to 8 float roundings, ~5e-7 relative.
constexpr double kInfoTol = 1e-6;
constexpr double kPi = 3.14159265358979323846;
// 95 % chi-square quantiles of the structure residuals (optim/optim.h, not config keys).
constexpr double kChi2Line4 = 9.488, kChi2Line1 = 3.841, kChi2Plane = 7.815;

std::string Family(const std::string& call_id) { return call_id.substr(0, call_id.find('#')); }
// "globalba" (issue 34, ref/loop: loop closing's global BA) is local BA over every keyframe.
bool BackboneFamily(const std::string& f) { return f == "track.pose" || f == "localba" || f == "globalba"; }

// "<landmark>@f<N>" / "<landmark>@kf<N>", landmark mp<id> (point), ml<id> (line), mpl<id> (plane).
struct ObsId {
  char type = 0;  // 'p' point, 'l' line, 'P' plane
  int64_t landmark = -1;
  bool keyframe = false;
  int64_t at = -1;  // frame or keyframe id
};

bool ParseObsId(const std::string& id, ObsId* o) {
  const size_t a = id.find('@');
  if (a == std::string::npos) return false;
  const std::string lm = id.substr(0, a), at = id.substr(a + 1);
  if (ParseNumberId(lm, "mpl", &o->landmark)) o->type = 'P';
  else if (ParseNumberId(lm, "mp", &o->landmark)) o->type = 'p';
  else if (ParseNumberId(lm, "ml", &o->landmark)) o->type = 'l';
  else return false;
  if (ParseNumberId(at, "kf", &o->at)) o->keyframe = true;
  else if (ParseNumberId(at, "f", &o->at)) o->keyframe = false;
  else return false;
  return true;
}

const char* IndexName(char type) { return type == 'p' ? "feature" : type == 'l' ? "line" : "plane"; }
std::string ItemId(char type, int64_t frame, int64_t index) {
  const std::string p = type == 'p' ? "f" : type == 'l' ? "l" : "pl";
  return p + std::to_string(frame) + "." + std::to_string(index);
}

std::optional<std::string> BackboneText(const TraceModel& t, const std::string& key) {
  const nlohmann::json& c = t.config();
  if (!c.is_object() || !c.contains("backbone") || !c.at("backbone").contains(key)) return std::nullopt;
  const nlohmann::json& p = c.at("backbone").at(key);
  const nlohmann::json& v = p.is_object() && p.contains("value") ? p.at("value") : p;
  return v.is_string() ? v.get<std::string>() : v.dump();
}

// g2o RobustKernelHuber rho(s) with delta^2 = d2.
double Huber(double s, double d2) { return s <= d2 ? s : 2.0 * std::sqrt(s * d2) - d2; }

// The keyframe's frame from its "track.keyframe" record.
std::optional<int64_t> KeyFrameFrame(const TraceModel& t, int64_t kf) {
  for (RecordRef ref : t.EntityRecords("kf" + std::to_string(kf))) {
    const Record& r = t.At(ref);
    if (r.type == RecordType::kProbability && r.stage == "track.keyframe")
      if (const auto f = Input(r, "frame")) return static_cast<int64_t>(*f);
  }
  return std::nullopt;
}

// The link record of the residual at `at`: the PROB of stage <family>.obs on the same observation
// id, the latest before it in its frame (the optimiser writes it right before the residual).
const Record* FindLink(const TraceModel& t, RecordRef at, const std::string& stage, const std::string& obs) {
  const auto& recs = t.frames()[at.frame_pos].records;
  if (at.index > 0) {
    const Record& r = recs[at.index - 1];
    if (r.type == RecordType::kProbability && r.stage == stage && r.entity == obs) return &r;
  }
  const Record* best = nullptr;
  for (RecordRef ref : t.EntityRecords(obs)) {
    if (ref.frame_pos != at.frame_pos || ref.index >= at.index) continue;
    const Record& r = t.At(ref);
    if (r.type == RecordType::kProbability && r.stage == stage) best = &r;
  }
  return best;
}

// The method weight of an observed item: the last PROB input `weight` of its entity in its frame
// before `at` (ref/verify/README.md), 1 when none.
double LastWeight(const TraceModel& t, const std::string& entity, size_t frame_pos, RecordRef at) {
  double w = 1.0;
  for (RecordRef ref : t.EntityRecords(entity)) {
    if (ref.frame_pos != frame_pos) continue;
    if (ref.frame_pos == at.frame_pos && ref.index >= at.index) break;
    const Record& r = t.At(ref);
    if (r.type != RecordType::kProbability) continue;
    if (const auto v = Input(r, "weight")) w = *v;
  }
  return w;
}

// 1 / sigma^2 of an octave: sigma = scale_factor^octave (ORB-SLAM2 ORBextractor); SIFT: one level
// per layer, 2^(1/3) with OpenCV's 3 layers, 24 levels (features/sift_extractor.cpp); onnx: 1 level.
std::optional<double> InvSigma2(const TraceModel& t, int64_t octave, std::string* why) {
  const std::string features = BackboneText(t, "features").value_or("orb");
  double factor = 0;
  int64_t levels = 0;
  if (features == "sift") {
    factor = std::pow(2.0, 1.0 / 3.0), levels = 24;
  } else if (features == "onnx") {
    factor = 2.0, levels = 1;
  } else {
    const auto f = t.BackboneNumber("scale_factor"), n = t.BackboneNumber("n_levels");
    if (!f || !n) {
      *why = "backbone scale_factor / n_levels";
      return std::nullopt;
    }
    factor = *f, levels = static_cast<int64_t>(*n);
  }
  if (octave < 0 || octave >= levels) {
    *why = "octave " + std::to_string(octave) + " outside the pyramid";
    return std::nullopt;
  }
  double scale = 1.0;
  for (int64_t i = 0; i < octave; ++i) scale *= factor;
  return 1.0 / (scale * scale);
}

// T_cw from a POSE record (rows of T_wc): R^T, -R^T t.
struct Pose {
  double R[3][3], t[3];
};
Pose CameraFromWorld(const Record& pose) {
  Pose p{};
  const auto& m = pose.T_wc;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) p.R[i][j] = m[static_cast<size_t>(j * 4 + i)];
  for (int i = 0; i < 3; ++i)
    p.t[i] = -(p.R[i][0] * m[3] + p.R[i][1] * m[7] + p.R[i][2] * m[11]);
  return p;
}

// ORB-SLAM2 residual obs - pi(T_cw X) of an RGB-D (3) or monocular (2) edge; false behind the camera.
bool ProjectionResidual(const CameraModel& K, const Pose& T, const double X[3], const double obs[3], int dof,
                        double e[3]) {
  double Xc[3];
  for (int i = 0; i < 3; ++i) Xc[i] = T.R[i][0] * X[0] + T.R[i][1] * X[1] + T.R[i][2] * X[2] + T.t[i];
  if (!(Xc[2] > 1e-9)) return false;
  const double inv_z = 1.0 / Xc[2];
  const double u = K.fx * Xc[0] * inv_z + K.cx, v = K.fy * Xc[1] * inv_z + K.cy;
  e[0] = obs[0] - u, e[1] = obs[1] - v;
  if (dof == 3) e[2] = obs[2] - (u - K.bf * inv_z);
  return true;
}

// Per frame: the POSE record (index) that starts / ends each track.pose call, when no other call
// lies between (the final call starts at POSE "initial"; a call followed by a POSE ends there).
struct CallPoses {
  std::map<std::string, long> start, end;  // call id -> record index of the POSE (-1 none)
};

CallPoses ComputeCallPoses(const std::vector<Record>& recs) {
  CallPoses cp;
  std::map<std::string, std::pair<size_t, size_t>> span;  // first, last residual index
  std::vector<std::string> order;
  for (size_t i = 0; i < recs.size(); ++i) {
    const Record& r = recs[i];
    if (r.type != RecordType::kResidual || Family(r.stage) != "track.pose") continue;
    auto it = span.find(r.stage);
    if (it == span.end()) span[r.stage] = {i, i}, order.push_back(r.stage);
    else it->second.second = i;
  }
  for (size_t c = 0; c < order.size(); ++c) {
    const auto [first, last] = span[order[c]];
    const size_t prev_end = c > 0 ? span[order[c - 1]].second : 0;
    const size_t next_start = c + 1 < order.size() ? span[order[c + 1]].first : recs.size();
    long s = -1, e = -1;
    for (size_t i = first; i-- > prev_end;)
      if (recs[i].type == RecordType::kPose) {
        if (recs[i].name == "initial") s = static_cast<long>(i);
        break;
      }
    for (size_t i = last + 1; i < next_start; ++i)
      if (recs[i].type == RecordType::kPose) {
        e = static_cast<long>(i);
        break;
      }
    cp.start[order[c]] = s, cp.end[order[c]] = e;
  }
  return cp;
}

// ---------------------------------------------------------------------------------------------
class ResidualVerifier final : public Verifier {
 public:
  bool Claims(const Record& r) const override {
    return r.type == RecordType::kResidual && BackboneFamily(Family(r.stage));
  }

  void Verify(const TraceModel& t, RecordRef at, Check& check) const override {
    const Record& r = t.At(at);
    const std::string family = Family(r.stage);
    const bool ba = family == "localba" || family == "globalba";
    ObsId id;
    if (!ParseObsId(r.entity, &id)) return check.Same("observation id", "mp|ml|mpl<id>@f|kf<n>", r.entity);
    check.Same("observation at", ba ? "keyframe" : "frame", id.keyframe ? "keyframe" : "frame");
    if (!ba) check.Near("observation frame", static_cast<double>(r.frame), static_cast<double>(id.at), 0);
    if (!check.ok()) return;
    const bool literal = t.BackboneNumber("line_literal_residual").value_or(0) != 0;
    if (!CheckKind(r, id, literal, check)) return;
    // The link record and the observed frame.
    const Record* link = FindLink(t, at, family + ".obs", r.entity);
    if (link == nullptr) return check.Missing("link record " + family + ".obs " + r.entity);
    const double index_d = check.Need(*link, IndexName(id.type));
    int64_t obs_frame = r.frame;
    if (ba) {
      const auto f = KeyFrameFrame(t, id.at);
      if (!f) return check.Missing("track.keyframe record of kf" + std::to_string(id.at));
      obs_frame = *f;
    }
    const auto fp = t.FramePos(obs_frame);
    if (!fp) return check.Missing("frame " + std::to_string(obs_frame));
    if (!check.ok()) return;
    const int64_t index = static_cast<int64_t>(index_d);
    // Weight: the method's per-observation weight (planes have none: 1 unless a stage records one).
    const double weight = LastWeight(t, ItemId(id.type, obs_frame, index), *fp, at);
    check.Near("weight", weight, r.weight, kTol);
    // Information, thresholds, chi2.
    Expected x;
    const bool valid = !r.residual_end.empty();
    double sq = 0;
    for (double e : r.residual_end) sq += e * e;
    if (id.type == 'p') {
      const PointEdge edge{at, link, *fp, index, obs_frame, ba};
      if (!ExpectPoint(t, edge, valid, sq, &x, check)) return;
    } else if (id.type == 'l') {
      if (!ExpectLine(t, r, literal, valid, sq, &x, check)) return;
    } else {
      if (!ExpectPlane(t, r, valid, &x, check)) return;
    }
    check.Near("chi2", x.chi2, r.chi2, kTol);
    check.Near("robust_loss", x.robust, r.robust_loss, kTol);
    // Inlier: pose-only re-classifies every edge at the returned pose (chi2 <= threshold); local
    // BA also drops the edges over the threshold after the robust phase (link robust_chi2).
    bool inlier = x.chi2 <= x.threshold;
    if (ba) {
      const double robust_chi2 = check.Need(*link, "robust_chi2");
      if (!check.ok()) return;
      inlier = inlier && robust_chi2 <= x.threshold;
    }
    check.Same("inlier", inlier, r.inlier);
  }

 private:
  // The recomputed outlier test of one residual.
  struct Expected {
    double threshold = 0, chi2 = kInf, robust = kInf;
  };
  // A point edge's record, link record and observed frame.
  struct PointEdge {
    RecordRef at;
    const Record* link;
    size_t frame_pos;
    int64_t index, obs_frame;
    bool ba;
  };

  // Kind and its dimension (residual sizes); false: stop (an unknown point kind).
  static bool CheckKind(const Record& r, const ObsId& id, bool literal, Check& check) {
    int dof = 0;
    if (id.type == 'p') {
      dof = r.residual_kind == "rgbd3" ? 3 : 2;
      if (r.residual_kind != "rgbd3" && r.residual_kind != "mono2") {
        check.Same("residual_kind", "rgbd3|mono2", r.residual_kind);
        return false;
      }
    } else if (id.type == 'l') {
      check.Same("residual_kind", literal ? "line1" : "line4", r.residual_kind);
      dof = literal ? 1 : 4;
    } else {
      check.Same("residual_kind", "plane3", r.residual_kind);
      dof = 3;
    }
    const auto size_ok = [&](const std::vector<double>& v) { return v.empty() || static_cast<int>(v.size()) == dof; };
    check.Near("residual_start size", size_ok(r.residual_start) ? 1 : 0, 1, 0);
    check.Near("residual_end size", size_ok(r.residual_end) ? 1 : 0, 1, 0);
    return true;
  }

  // A point edge: information from the OBS octave, rgbd3 / mono2 from its virtual right
  // coordinate, threshold from the backbone options; pose-only residuals recomputed. False: stop.
  bool ExpectPoint(const TraceModel& t, const PointEdge& edge, bool valid, double sq, Expected* x,
                   Check& check) const {
    const Record& r = t.At(edge.at);
    const std::string pre = edge.ba ? "ba_" : "pose_";
    const Record* obs = t.Obs(edge.frame_pos, edge.index);
    if (obs == nullptr) {
      check.Missing("OBS f" + std::to_string(edge.obs_frame) + "." + std::to_string(edge.index));
      return false;
    }
    std::string why;
    const auto info = InvSigma2(t, obs->octave, &why);
    if (!info) return check.Missing(why), false;
    check.Near("information", *info, r.information, kInfoTol);
    // rgbd3 iff the feature has a virtual right coordinate u_r = u - bf / depth >= 0, in float32
    // as the frame stores it (ORB-SLAM2 ComputeStereoFromRGBD, mvuRight).
    if (!t.camera().present) return check.Missing("header camera_json"), false;
    float ur = -1.0f;
    if (obs->depth_m > 0) ur = static_cast<float>(obs->u) - static_cast<float>(t.camera().bf) / static_cast<float>(obs->depth_m);
    const bool stereo = obs->depth_m > 0 && ur >= 0;
    check.Same("residual_kind", stereo ? "rgbd3" : "mono2", r.residual_kind);
    const auto th = t.BackboneNumber(pre + (stereo ? "chi2_stereo" : "chi2_mono"));
    const auto weighted_test = t.BackboneNumber(pre + "weighted_outlier_test");
    x->threshold = check.Need(th, "backbone " + pre + "chi2");
    check.Need(weighted_test, "backbone " + pre + "weighted_outlier_test");
    if (!check.ok()) return false;
    // chi2 = e^T Omega e with Omega = inv_sigma2 * I (outlier test; * weight when weighted).
    const double test_info = *weighted_test != 0 ? r.information * r.weight : r.information;
    if (valid) x->chi2 = test_info * sq, x->robust = Huber(r.information * r.weight * sq, x->threshold);
    if (!edge.ba) CheckProjection(t, edge.at, *edge.link, *obs, ur, stereo ? 3 : 2, check);
    return true;
  }

  static bool ExpectLine(const TraceModel& t, const Record& r, bool literal, bool valid, double sq, Expected* x,
                         Check& check) {
    const double sigma = check.Need(t.BackboneNumber("line_sigma_px"), "backbone line_sigma_px");
    if (!check.ok()) return false;
    check.Near("information", 1.0 / (sigma * sigma), r.information, kTol);
    x->threshold = literal ? kChi2Line1 : kChi2Line4;
    if (valid) x->chi2 = sq / (sigma * sigma), x->robust = Huber(r.weight * x->chi2, x->threshold);
    return true;
  }

  static bool ExpectPlane(const TraceModel& t, const Record& r, bool valid, Expected* x, Check& check) {
    const double sa_deg = check.Need(t.BackboneNumber("plane_angle_sigma_deg"), "backbone plane_angle_sigma_deg");
    const double sd = check.Need(t.BackboneNumber("plane_dist_sigma_m"), "backbone plane_dist_sigma_m");
    if (!check.ok()) return false;
    check.Near("information", 1.0 / (sd * sd), r.information, kTol);
    x->threshold = kChi2Plane;
    const double sa = sa_deg * kPi / 180;
    if (valid) {
      const auto& e = r.residual_end;
      x->chi2 = (e[0] * e[0] + e[1] * e[1]) / (sa * sa) + e[2] * e[2] / (sd * sd);
      x->robust = Huber(r.weight * x->chi2, x->threshold);
    }
    return true;
  }

  // residual_start / residual_end of a pose-only point edge recomputed from the link's world point,
  // the OBS and the POSE records that bound the call (CallPoses); calls without one are not.
  void CheckProjection(const TraceModel& t, RecordRef at, const Record& link, const Record& obs, float ur, int dof,
                       Check& check) const {
    if (cache_model_ != &t) cache_.clear(), cache_model_ = &t;
    auto it = cache_.find(at.frame_pos);
    if (it == cache_.end()) it = cache_.emplace(at.frame_pos, ComputeCallPoses(t.frames()[at.frame_pos].records)).first;
    const Record& r = t.At(at);
    const long s = it->second.start.count(r.stage) ? it->second.start.at(r.stage) : -1;
    const long e = it->second.end.count(r.stage) ? it->second.end.at(r.stage) : -1;
    if (s < 0 && e < 0) return;
    const double X[3] = {check.Need(link, "x"), check.Need(link, "y"), check.Need(link, "z")};
    if (!check.ok()) return;
    const double o[3] = {obs.u, obs.v, static_cast<double>(ur)};
    const auto compare = [&](long pose_index, const std::vector<double>& recorded, const std::string& field) {
      if (pose_index < 0) return;
      const Pose T = CameraFromWorld(t.frames()[at.frame_pos].records[static_cast<size_t>(pose_index)]);
      double res[3];
      const bool ok = ProjectionResidual(t.camera(), T, X, o, dof, res);
      check.Near(field + " size", ok ? dof : 0, static_cast<double>(recorded.size()), 0);
      if (!check.ok() || !ok) return;
      for (int k = 0; k < dof; ++k)
        check.Near(field + "[" + std::to_string(k) + "]", res[k], recorded[static_cast<size_t>(k)], kTol);
    };
    compare(s, r.residual_start, "start");
    compare(e, r.residual_end, "end");
  }
  mutable const TraceModel* cache_model_ = nullptr;
  mutable std::map<size_t, CallPoses> cache_;
};

// ---------------------------------------------------------------------------------------------
// Link records: p = 0 carriers naming the frame item a residual observes (optim/optim.h).
class LinkVerifier final : public Verifier {
 public:
  bool Claims(const Record& r) const override {
    if (r.type != RecordType::kProbability) return false;
    return r.stage == "track.pose.obs" || r.stage == "localba.obs" || r.stage == "globalba.obs";
  }
  void Verify(const TraceModel& t, RecordRef at, Check& check) const override {
    const Record& r = t.At(at);
    const bool ba = r.stage == "localba.obs" || r.stage == "globalba.obs";
    check.Near("before", 0, r.before, 0);
    check.Near("after", 0, r.after, 0);
    ObsId id;
    if (!ParseObsId(r.entity, &id)) return check.Same("entity", "mp|ml|mpl<id>@f|kf<n>", r.entity);
    check.Same("observation at", ba ? "keyframe" : "frame", id.keyframe ? "keyframe" : "frame");
    const double index = check.Need(r, IndexName(id.type));
    if (ba) check.Need(r, "robust_chi2");
    else if (id.type == 'p') check.Need(r, "x"), check.Need(r, "y"), check.Need(r, "z");
    if (!check.ok()) return;
    // The residual it links follows in the same frame.
    const std::string family = ba ? r.stage.substr(0, r.stage.size() - 4) : "track.pose";
    const auto& recs = t.frames()[at.frame_pos].records;
    bool linked = false;
    for (size_t i = at.index + 1; i < recs.size() && !linked; ++i) {
      const Record& n = recs[i];
      if (n.entity != r.entity) continue;
      if (n.type == RecordType::kResidual && Family(n.stage) == family) linked = true;
      else if (n.type == RecordType::kProbability && n.stage == r.stage) break;
    }
    check.Same("residual after the link", true, linked);
    // The named frame item exists.
    int64_t frame = r.frame;
    if (ba) {
      const auto f = KeyFrameFrame(t, id.at);
      if (!f) return check.Missing("track.keyframe record of kf" + std::to_string(id.at));
      frame = *f;
    } else {
      check.Near("observation frame", static_cast<double>(r.frame), static_cast<double>(id.at), 0);
    }
    const auto fp = t.FramePos(frame);
    if (!fp) return check.Missing("frame " + std::to_string(frame));
    const int64_t i = static_cast<int64_t>(index);
    if (id.type == 'p') {
      if (t.Obs(*fp, i) == nullptr) check.Missing("OBS f" + std::to_string(frame) + "." + std::to_string(i));
      return;
    }
    bool found = false;
    for (RecordRef ref : t.EntityRecords(ItemId(id.type, frame, i)))
      if (ref.frame_pos == *fp && t.At(ref).stage == trace::kGeometryStage) found = true;
    if (!found) check.Missing("structure record " + ItemId(id.type, frame, i));
  }
};

// Keyframe records: kf<id> made in the frame its input `frame` names, once.
class KeyFrameVerifier final : public Verifier {
 public:
  bool Claims(const Record& r) const override {
    return r.type == RecordType::kProbability && r.stage == "track.keyframe";
  }
  void Verify(const TraceModel& t, RecordRef at, Check& check) const override {
    const Record& r = t.At(at);
    int64_t kf = -1;
    if (!ParseNumberId(r.entity, "kf", &kf)) return check.Same("entity", "kf<id>", r.entity);
    check.Same("kind", "keyframe", trace::EntityKindName(r.kind));
    check.Near("before", 0, r.before, 0);
    check.Near("after", 0, r.after, 0);
    check.Near("frame", static_cast<double>(r.frame), check.Need(r, "frame"), 0);
    for (RecordRef ref : t.EntityRecords(r.entity)) {
      const Record& o = t.At(ref);
      if (o.type != RecordType::kProbability || o.stage != r.stage) continue;
      check.Same("first track.keyframe record of " + r.entity, true, ref.frame_pos == at.frame_pos && ref.index == at.index);
      break;
    }
  }
};

// Structure records (ref/structure/README.md "Trace"): frame lines and planes, p = 0. The map
// landmark they name is the one an inlier residual of the frame's last pose-only call links to
// them, -1 without one, or a landmark the frame's keyframe created.
class StructureVerifier final : public Verifier {
 public:
  bool Claims(const Record& r) const override {
    return r.type == RecordType::kProbability && r.stage == trace::kGeometryStage;
  }
  void Verify(const TraceModel& t, RecordRef at, Check& check) const override {
    const Record& r = t.At(at);
    check.Near("before", 0, r.before, 0);
    check.Near("after", 0, r.after, 0);
    const bool line = r.kind == trace::EntityKind::kLineSample;
    int64_t frame = -1, index = -1;
    if (!ParseDottedId(r.entity, line ? "l" : "pl", &frame, &index) ||
        (!line && r.kind != trace::EntityKind::kPlane))
      return check.Same("entity", "l<frame>.<i> (line_sample) | pl<frame>.<j> (plane)", r.entity);
    check.Near("entity frame", static_cast<double>(r.frame), static_cast<double>(frame), 0);
    const char* names_line[] = {"x0", "y0", "x1", "y1", "map_line", "has_3d", "group"};
    const char* names_plane[] = {"x_min", "y_min", "x_max", "y_max", "n_x", "n_y", "n_z", "d", "points", "map_plane"};
    if (line)
      for (const char* n : names_line) check.Need(r, n);
    else
      for (const char* n : names_plane) check.Need(r, n);
    if (!check.ok()) return;
    if (line) {
      const double h = *Input(r, "has_3d");
      check.Same("has_3d in {0,1}", true, h == 0 || h == 1);
    } else {
      const double nx = *Input(r, "n_x"), ny = *Input(r, "n_y"), nz = *Input(r, "n_z");
      check.Near("|n|", 1.0, std::sqrt(nx * nx + ny * ny + nz * nz), 1e-9);
      check.Same("bounding box", true, *Input(r, "x_min") <= *Input(r, "x_max") && *Input(r, "y_min") <= *Input(r, "y_max"));
    }
    const double recorded = *Input(r, line ? "map_line" : "map_plane");
    // Landmark from the last pose-only call's inlier residuals linked to this item.
    const auto& recs = t.frames()[at.frame_pos].records;
    std::string last_call;
    for (size_t i = 0; i < at.index; ++i)
      if (recs[i].type == RecordType::kResidual && Family(recs[i].stage) == "track.pose") last_call = recs[i].stage;
    double expected = -1;
    const std::string prefix = line ? "ml" : "mpl";
    for (size_t i = 1; i < at.index && !last_call.empty(); ++i) {
      const Record& res = recs[i];
      if (res.type != RecordType::kResidual || res.stage != last_call || !res.inlier) continue;
      const Record& link = recs[i - 1];
      ObsId id;
      if (link.stage != "track.pose.obs" || link.entity != res.entity || !ParseObsId(res.entity, &id)) continue;
      if ((line ? id.type != 'l' : id.type != 'P')) continue;
      const auto li = Input(link, line ? "line" : "plane");
      if (li && static_cast<int64_t>(*li) == index) expected = static_cast<double>(id.landmark);
    }
    if (expected < 0 && recorded >= 0) {
      // A keyframe made in this frame creates landmarks for its unassociated lines / planes.
      bool keyframe = false;
      for (size_t i = 0; i < at.index && !keyframe; ++i)
        keyframe = recs[i].type == RecordType::kProbability && recs[i].stage == "track.keyframe";
      if (keyframe) expected = recorded;
    }
    check.Near(line ? "map_line" : "map_plane", expected, recorded, 0);
  }
};

}  // namespace

void AddBackboneVerifiers(VerifierList& out) {
  out.push_back(std::make_unique<ResidualVerifier>());
  out.push_back(std::make_unique<LinkVerifier>());
  out.push_back(std::make_unique<KeyFrameVerifier>());
  out.push_back(std::make_unique<StructureVerifier>());
}

}  // namespace dynref::verify
