// Verifiers of the MGD-SLAM records (ref/verify/README.md, section "MGD-SLAM"). Written from
// seed 000 (spec 000 steps 6-15) and ref/dynamic/mgd/README.md "Trace"; never calls the stage code.
// One verifier claims every PROB record of the mgd.* stages and the DECISION records of
// mgd.probability / mgd.boxes; it indexes each frame's mgd records once (by feature index, or by
// line and sample) and recomputes:
//   mgd.boxes       Sec. 3.4: P_init = 0.5 in a box, 0 outside (initialisation frame); weight.
//   mgd.frame       Sec. 3.5 / E6: vbar = mean (x^k - x^{k-1}) of the out-of-box corresponded
//                   features; F usable iff both poses and |t_{k,k-1}| > 1e-9.
//   mgd.inherit     Sec. 3.4 (step 7): previous-frame P, else the map point's / map line's P,
//                   else P_init(Flag_d); the descriptor gate (1 - delta) 256 bits.
//   mgd.P_LS        Sec. 3.5 (step 8a): P_LS = sig(a_LS (d - d_th) + (1 - a_LS)(dtheta - theta_th)).
//   mgd.P_pro       Sec. 3.5 (step 8b, E7): the cached cue of mgd.reprojection.
//   mgd.P_mf        Sec. 3.5 (step 8c, E9): d = |x^kT F x^{k-1}| / ||(F x^{k-1})_12||, F = K^-T [t]x R K^-1.
//   mgd.fusion      Sec. 3.5 (step 8d): S = sig(sum_c w_c logit(P_c)).
//   mgd.smooth      Sec. 3.4 (step 9, E1): P = (1 - a) P_prev + a S.
//   mgd.diffuse     Sec. 3.4 (step 10, E11): Jacobi diffusion over 3-D neighbours within r.
//   mgd.map_point   step 15: a map point's P is the diffused P of the feature written to it.
//   mgd.line        step 11: the line's P = largest sample; weight 0 above tau_dyn else 1 - P.
//   mgd.reprojection Sec. 3.5 (step 8b): P_pro = sig(a_pro ((fwd + bwd) / 2 - d_th_pro)).
//   decisions       Sec. 3.6 (step 13): kept iff P <= tau_dyn.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <tuple>

#include "verify/verifier.h"

namespace dynref::verify {
namespace {

using trace::EntityKind;
using trace::Record;
using trace::RecordType;

// The epipolar distance goes through this frame's initial POSE record, stored as T_wc and
// inverted here (the stage holds T_cw): F differs in the last bits, d_epi by ~1e-12 px.
constexpr double kEpiTol = 1e-8;
constexpr double kClampP = 1e-6;  // spec 000 step 8d: P clamped to [1e-6, 1 - 1e-6] before logit

double Sig(double z) { return 1.0 / (1.0 + std::exp(-z)); }
double LogOdds(double p) {
  const double q = std::min(std::max(p, kClampP), 1.0 - kClampP);
  return std::log(q / (1.0 - q));
}

// Position of a record in processing order.
bool Earlier(RecordRef a, RecordRef b) {
  return a.frame_pos != b.frame_pos ? a.frame_pos < b.frame_pos : a.index < b.index;
}

// The method's parameters (configs/mgd*.yaml, mgd.probability params) as the config_json holds them.
struct Params {
  std::optional<double> p_init_box, p_init_free, delta, a_ls, d_th_ls, theta_th, min_velocity, d_th_pro, a_pro,
      d_th_mf, a_mf, use_ls, use_pro, use_mf, w_ls, w_pro, w_mf, a, diffusion, radius, tau;
  std::string angle_form, smoothing, weight, line_cue_form, features;
};

Params ReadParams(const TraceModel& t) {
  Params p;
  const std::string s = "mgd.probability";
  auto num = [&](const char* k) { return t.StageNumber(s, k); };
  auto text = [&](const char* k) {
    std::string v;
    t.StageParam(s, k, &v);
    return v;
  };
  p.p_init_box = num("p_init_box"), p.p_init_free = num("p_init_free"), p.delta = num("delta");
  p.a_ls = num("a_ls"), p.d_th_ls = num("d_th_ls_px"), p.theta_th = num("theta_th_ls_rad");
  p.min_velocity = num("min_velocity_px"), p.d_th_pro = num("d_th_pro_px"), p.a_pro = num("a_pro");
  p.d_th_mf = num("d_th_mf_px"), p.a_mf = num("a_mf"), p.use_ls = num("use_ls"), p.use_pro = num("use_pro");
  p.use_mf = num("use_mf"), p.w_ls = num("w_ls"), p.w_pro = num("w_pro"), p.w_mf = num("w_mf"), p.a = num("a");
  p.diffusion = num("diffusion"), p.radius = num("radius_m"), p.tau = num("tau_dyn");
  p.angle_form = text("angle_form"), p.smoothing = text("smoothing"), p.weight = text("weight");
  p.line_cue_form = text("line_cue_form");
  const nlohmann::json& c = t.config();
  if (c.is_object() && c.contains("backbone") && c.at("backbone").contains("features")) {
    const nlohmann::json& f = c.at("backbone").at("features");
    const nlohmann::json& v = f.is_object() && f.contains("value") ? f.at("value") : f;
    p.features = v.is_string() ? v.get<std::string>() : v.dump();
  } else {
    p.features = "orb";  // the backbone default
  }
  return p;
}

// Weight of a kept observation (spec E13): 1 - P, or 1 with weight: none.
double KeptWeight(const Params& p, double P) { return p.weight == "none" ? 1.0 : 1.0 - P; }

// A frame's mgd records by feature index (sample -1) or by line index and sample (-1: the line).
struct FrameIndex {
  bool indexed = false;
  std::map<std::tuple<int, int64_t, int, std::string>, size_t> recs;  // (0 feature | 1 line, i, sample, stage)
  std::optional<size_t> frame_rec;                                    // mgd.frame
  // Lazily: the Jacobi diffusion recomputed over every node of the frame.
  bool diffused = false;
  std::map<std::pair<int, std::pair<int64_t, int>>, std::pair<double, int>> diffusion;  // node -> (P', |N|)
  bool vbar_done = false;
  Eigen::Vector2d vbar = Eigen::Vector2d::Zero();
  int n_vbar = 0;
  bool vbar_complete = true;  // every OBS the mean needs was found
};

class MgdVerifier final : public Verifier {
 public:
  bool Claims(const Record& r) const override {
    if (r.type == RecordType::kDecision) return r.stage == "mgd.probability" || r.stage == "mgd.boxes";
    if (r.type != RecordType::kProbability) return false;
    static const char* kStages[] = {"mgd.boxes", "mgd.frame", "mgd.inherit", "mgd.P_LS", "mgd.P_pro",
                                    "mgd.P_mf", "mgd.fusion", "mgd.smooth", "mgd.diffuse", "mgd.map_point",
                                    "mgd.line", "mgd.reprojection"};
    for (const char* s : kStages)
      if (r.stage == s) return true;
    return false;
  }

  void Verify(const TraceModel& t, RecordRef at, Check& c) const override {
    Bind(t);
    const Record& r = t.At(at);
    if (r.type == RecordType::kDecision) return VerifyDecision(t, at, c);
    if (r.stage == "mgd.reprojection") return VerifyReprojection(r, c);
    if (r.stage == "mgd.map_point") return VerifyMapPoint(t, at, c);
    if (r.stage == "mgd.frame") return VerifyFrame(t, at, c);
    Node n;
    if (!ParseNode(r, &n)) return c.Same("entity", "f<frame>.<i> or l<frame>.<i>", r.entity);
    if (r.stage == "mgd.boxes") return VerifyBoxes(t, at, n, c);
    if (r.stage == "mgd.line") return VerifyLine(t, at, n, c);
    if (n.sample < 0) return c.Missing("input sample");
    if (r.stage == "mgd.inherit") return VerifyInherit(t, at, n, c);
    if (r.stage == "mgd.P_LS") return VerifyLS(t, at, n, c);
    if (r.stage == "mgd.P_pro") return VerifyPro(t, at, n, c);
    if (r.stage == "mgd.P_mf") return VerifyMF(t, at, n, c);
    if (r.stage == "mgd.fusion") return VerifyFusion(t, at, n, c);
    if (r.stage == "mgd.smooth") return VerifySmooth(t, at, n, c);
    if (r.stage == "mgd.diffuse") return VerifyDiffuse(t, at, n, c);
  }

 private:
  // A feature (line = false, sample 0) or a line sample / line (sample -1) of frame `frame`.
  struct Node {
    bool line = false;
    int64_t frame = -1, index = -1;
    int sample = 0;
  };

  mutable const TraceModel* bound_ = nullptr;
  mutable std::string bound_path_;
  mutable Params params_;
  mutable std::map<size_t, FrameIndex> frames_;
  mutable bool lines_indexed_ = false;
  mutable std::map<int64_t, std::vector<std::pair<RecordRef, double>>> map_line_p_;  // mgd.line writes

  void Bind(const TraceModel& t) const {
    if (bound_ == &t && bound_path_ == t.path()) return;
    bound_ = &t, bound_path_ = t.path();
    params_ = ReadParams(t);
    frames_.clear();
    lines_indexed_ = false;
    map_line_p_.clear();
  }

  static bool ParseNode(const Record& r, Node* n) {
    if (r.kind == EntityKind::kFeature) {
      n->line = false, n->sample = 0;
      return ParseDottedId(r.entity, "f", &n->frame, &n->index);
    }
    if (r.kind != EntityKind::kLineSample || !ParseDottedId(r.entity, "l", &n->frame, &n->index)) return false;
    n->line = true;
    const std::optional<double> s = Input(r, "sample");
    n->sample = s ? static_cast<int>(*s) : -1;
    return true;
  }

  const FrameIndex& Index(const TraceModel& t, size_t fp) const {
    FrameIndex& fi = frames_[fp];
    if (fi.indexed) return fi;
    fi.indexed = true;
    const std::vector<Record>& recs = t.frames()[fp].records;
    for (size_t i = 0; i < recs.size(); ++i) {
      const Record& r = recs[i];
      if (r.type != RecordType::kProbability || r.stage.compare(0, 4, "mgd.") != 0) continue;
      if (r.stage == "mgd.frame") {
        fi.frame_rec = i;
        continue;
      }
      Node n;
      if (!ParseNode(r, &n)) continue;
      const int sample = n.line ? n.sample : -1;
      // mgd.boxes weight carriers of the initial pose are not the initialisation frame's P_init.
      const bool carrier = r.stage == "mgd.boxes" && (Input(r, "initial_pose") || Input(r, "lost"));
      fi.recs[{n.line ? 1 : 0, n.index, sample, carrier ? "mgd.boxes.carrier" : r.stage}] = i;
    }
    return fi;
  }

  // The record of `stage` on node (line, index, sample) in frame group fp (nullptr if none).
  const Record* Find(const TraceModel& t, size_t fp, bool line, int64_t index, int sample, const std::string& stage) const {
    const FrameIndex& fi = Index(t, fp);
    auto it = fi.recs.find({line ? 1 : 0, index, line ? sample : -1, stage});
    return it == fi.recs.end() ? nullptr : &t.frames()[fp].records[it->second];
  }
  const Record* Find(const TraceModel& t, size_t fp, const Node& n, const std::string& stage) const {
    return Find(t, fp, n.line, n.index, n.sample, stage);
  }
  const Record* FrameRecord(const TraceModel& t, size_t fp) const {
    const FrameIndex& fi = Index(t, fp);
    return fi.frame_rec ? &t.frames()[fp].records[*fi.frame_rec] : nullptr;
  }

  // The P a node ended frame group fp with (its diffused P, or the initialisation frame's P_init).
  std::optional<double> FinalP(const TraceModel& t, size_t fp, bool line, int64_t index, int sample) const {
    if (const Record* d = Find(t, fp, line, index, sample, "mgd.diffuse")) return d->after;
    if (const Record* b = Find(t, fp, line, index, sample, "mgd.boxes")) return b->after;
    return std::nullopt;
  }

  // ---- configuration helpers ----
  double Need(Check& c, const std::optional<double>& v, const char* key) const {
    return c.Need(v, std::string("config mgd.probability.") + key);
  }
  double PInit(Check& c, double in_box) const {
    return in_box != 0 ? Need(c, params_.p_init_box, "p_init_box") : Need(c, params_.p_init_free, "p_init_free");
  }

  // ---- mgd.boxes on a lost frame: an in-box feature's box-prior weight for relocalisation ----
  void VerifyLostCarrier(const Record& r, Check& c) const {
    const double tau = Need(c, params_.tau, "tau_dyn");
    const double p = Need(c, params_.p_init_box, "p_init_box");
    const double in_box = c.Need(r, "in_box");
    const double w = c.Need(r, "weight");
    if (!c.ok()) return;
    c.Near("in_box", 1, in_box, 0);
    c.Near("weight", p > tau ? 0.0 : KeptWeight(params_, p), w, kTol);
    c.Near("before", 0, r.before, 0);
    c.Near("after", 0, r.after, 0);
  }

  // ---- mgd.boxes: the initialisation frame's P_init per feature / line sample, the line's weight ----
  void VerifyBoxes(const TraceModel& t, RecordRef at, const Node& n, Check& c) const {
    const Record& r = t.At(at);
    if (Input(r, "lost")) return VerifyLostCarrier(r, c);
    if (Input(r, "initial_pose")) {  // weight carrier: weight 0 for the initial pose (spec E10), p = 0
      std::string out_of_box;
      t.StageParam("mgd.probability", "initial_pose_out_of_box", &out_of_box);
      c.Same("config mgd.probability.initial_pose_out_of_box", std::string("true"), out_of_box);
      double in_box = 0;
      if (n.line) {
        for (const char* k : {"in_box_s", "in_box_m", "in_box_e"}) in_box = std::max(in_box, c.Need(r, k));
      } else {
        in_box = c.Need(r, "in_box");
      }
      const double w = c.Need(r, "weight");
      if (!c.ok()) return;
      c.Near("in_box", 1, in_box, 0);
      c.Near("weight", 0, w, 0);
      c.Near("before", 0, r.before, 0);
      return c.Near("after", 0, r.after, 0);
    }
    const double tau = Need(c, params_.tau, "tau_dyn");
    if (n.line && n.sample < 0) {  // the line: its largest sample and weight
      double p_max = 0;
      for (int k = 0; k < 3; ++k) {
        const Record* s = Find(t, at.frame_pos, true, n.index, k, "mgd.boxes");
        if (s == nullptr) return c.Missing("mgd.boxes record of sample " + std::to_string(k));
        p_max = std::max(p_max, s->after);
      }
      const double w = c.Need(r, "weight");
      if (!c.ok()) return;
      c.Near("before", p_max, r.before, kTol);
      c.Near("after", p_max, r.after, kTol);
      c.Near("weight", p_max > tau ? 0.0 : KeptWeight(params_, p_max), w, kTol);
      return;
    }
    const double in_box = c.Need(r, "in_box");
    const double p = PInit(c, in_box);
    if (!c.ok()) return;
    c.Near("before", p, r.before, kTol);
    c.Near("after", p, r.after, kTol);
    if (!n.line) c.Near("weight", p > tau ? 0.0 : KeptWeight(params_, p), c.Need(r, "weight"), kTol);
  }

  // ---- mgd.frame: previous frame, mean background flow, F usable ----
  // vbar over the frame's out-of-box features with a correspondence (their mgd.inherit records):
  // v = x^k - x^{k-1} of the OBS u, v (undistorted keypoints, float in the stage: the difference is
  // taken in float as there), summed in feature-index order.
  const FrameIndex& Vbar(const TraceModel& t, size_t fp, int64_t prev_frame) const {
    FrameIndex& fi = frames_[fp];
    Index(t, fp);
    if (fi.vbar_done) return fi;
    fi.vbar_done = true;
    const std::optional<size_t> pp = t.FramePos(prev_frame);
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int count = 0;
    for (const auto& [key, idx] : fi.recs) {  // ascending (kind, index): features first, by index
      if (std::get<0>(key) != 0 || std::get<3>(key) != "mgd.inherit") continue;
      const Record& r = t.frames()[fp].records[idx];
      const std::optional<double> j = Input(r, "prev_index"), box = Input(r, "in_box");
      if (!j || !box) {
        fi.vbar_complete = false;
        continue;
      }
      if (*j < 0 || *box != 0) continue;
      const Record* a = t.Obs(fp, std::get<1>(key));
      const Record* b = pp ? t.Obs(*pp, static_cast<int64_t>(*j)) : nullptr;
      if (a == nullptr || b == nullptr) {
        fi.vbar_complete = false;
        continue;
      }
      const float du = static_cast<float>(a->u) - static_cast<float>(b->u);
      const float dv = static_cast<float>(a->v) - static_cast<float>(b->v);
      sum += Eigen::Vector2d(du, dv);
      ++count;
    }
    fi.n_vbar = count;
    if (count > 0) fi.vbar = sum / count;
    return fi;
  }

  // This frame's T_cw from its initial POSE record (T_wc), nullopt if none.
  static std::optional<Eigen::Isometry3d> InitialTcw(const TraceModel& t, size_t fp) {
    for (const Record& r : t.frames()[fp].records)
      if (r.type == RecordType::kPose && r.name == "initial") {
        Eigen::Matrix3d R;
        Eigen::Vector3d p;
        for (int i = 0; i < 3; ++i) {
          for (int j = 0; j < 3; ++j) R(i, j) = r.T_wc[4 * i + j];
          p(i) = r.T_wc[4 * i + 3];
        }
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = R.transpose();
        T.translation() = -(R.transpose() * p);
        return T;
      }
    return std::nullopt;
  }

  // T_{k,k-1} = T_cw(k, initial POSE) * T_cw(k-1 as the stage saw it, mgd.frame prev_T_cw)^-1.
  std::optional<Eigen::Isometry3d> RelativePose(const TraceModel& t, size_t fp, const Record& fr, Check& c) const {
    if (Input(fr, "has_T").value_or(0) == 0) return std::nullopt;
    Eigen::Matrix3d R;
    Eigen::Vector3d p;
    for (int i = 0; i < 12; ++i) {
      const double v = c.Need(fr, "prev_T_cw[" + std::to_string(i) + "]");
      if (i % 4 == 3) p(i / 4) = v;
      else R(i / 4, i % 4) = v;
    }
    const std::optional<Eigen::Isometry3d> cur = InitialTcw(t, fp);
    if (!cur) {
      c.Missing("initial POSE record of frame " + std::to_string(t.frames()[fp].frame));
      return std::nullopt;
    }
    if (!c.ok()) return std::nullopt;
    Eigen::Isometry3d prev_inv = Eigen::Isometry3d::Identity();
    prev_inv.linear() = R.transpose();
    prev_inv.translation() = -(R.transpose() * p);
    return Eigen::Isometry3d(*cur * prev_inv);
  }

  void VerifyFrame(const TraceModel& t, RecordRef at, Check& c) const {
    const Record& r = t.At(at);
    int64_t frame = -1;
    if (!ParseNumberId(r.entity, "f", &frame) || frame != t.frames()[at.frame_pos].frame)
      return c.Same("entity", "f" + std::to_string(t.frames()[at.frame_pos].frame), r.entity);
    const double prev = c.Need(r, "prev_frame");
    const double n_vbar = c.Need(r, "n_vbar"), vu = c.Need(r, "vbar_u"), vv = c.Need(r, "vbar_v");
    const double has_T = c.Need(r, "has_T"), has_F = c.Need(r, "has_F");
    if (!c.ok()) return;
    c.Near("before", 0, r.before, 0);
    c.Near("after", 0, r.after, 0);
    if (prev >= 0 && prev >= static_cast<double>(frame)) c.Near("prev_frame < frame", frame - 1, prev, 0);
    const FrameIndex& fi = Vbar(t, at.frame_pos, static_cast<int64_t>(prev));
    if (!fi.vbar_complete) return c.Missing("an OBS or mgd.inherit input of the mean flow");
    c.Near("n_vbar", fi.n_vbar, n_vbar, 0);
    c.Near("vbar_u", fi.vbar.x(), vu, kTol);
    c.Near("vbar_v", fi.vbar.y(), vv, kTol);
    if (has_T != 0) {
      const std::optional<Eigen::Isometry3d> T = RelativePose(t, at.frame_pos, r, c);
      if (!T) return;
      c.Near("has_F", T->translation().norm() > 1e-9 ? 1 : 0, has_F, 0);
    } else {
      c.Near("has_F", 0, has_F, 0);
    }
  }

  // ---- mgd.inherit: step 7 ----
  // The map point's P before record `at`: the last mgd.map_point write on it.
  static std::optional<double> MapPointP(const TraceModel& t, int64_t mp, RecordRef at) {
    std::optional<double> p;
    for (const RecordRef& ref : t.EntityRecords("mp" + std::to_string(mp))) {
      if (!Earlier(ref, at)) break;
      const Record& r = t.At(ref);
      if (r.type == RecordType::kProbability && r.stage == "mgd.map_point") p = r.after;
    }
    return p;
  }
  // The map line's P before record `at`: the last mgd.line record of a line associated with it.
  std::optional<double> MapLineP(const TraceModel& t, int64_t ml, RecordRef at) const {
    if (!lines_indexed_) {
      lines_indexed_ = true;
      for (size_t fp = 0; fp < t.frames().size(); ++fp) {
        const std::vector<Record>& recs = t.frames()[fp].records;
        for (size_t i = 0; i < recs.size(); ++i) {
          const Record& r = recs[i];
          if (r.type != RecordType::kProbability || r.stage != "mgd.line") continue;
          const std::optional<double> m = Input(r, "map_line");
          if (m && *m >= 0) map_line_p_[static_cast<int64_t>(*m)].push_back({RecordRef{fp, i}, r.after});
        }
      }
    }
    std::optional<double> p;
    auto it = map_line_p_.find(ml);
    if (it == map_line_p_.end()) return p;
    for (const auto& [ref, v] : it->second) {
      if (!Earlier(ref, at)) break;
      p = v;
    }
    return p;
  }

  void VerifyInherit(const TraceModel& t, RecordRef at, const Node& n, Check& c) const {
    const Record& r = t.At(at);
    const Record* fr = FrameRecord(t, at.frame_pos);
    if (fr == nullptr) return c.Missing("mgd.frame record of the frame");
    const double prev_frame = c.Need(*fr, "prev_frame");
    const double source = c.Need(r, "source"), j = c.Need(r, "prev_index"), in_box = c.Need(r, "in_box");
    const double hamming = c.Need(r, "hamming");
    const double landmark = c.Need(r, n.line ? "map_line" : "map_point");
    const double kp = n.line ? c.Need(r, "prev_sample") : 0;
    const double p_init = PInit(c, in_box);
    if (!c.ok()) return;
    if (n.line && j >= 0 && kp != n.sample && kp != 2 - n.sample)
      c.Near("prev_sample", n.sample, kp, 0);
    // Descriptor gate of the correspondence (spec E3, delta read as a similarity).
    if (!n.line && j >= 0) {
      const double delta = Need(c, params_.delta, "delta");
      const double max_dist = params_.features == "orb" ? std::floor((1.0 - delta) * 256.0) : (1.0 - delta) * 4.0;
      if (c.ok() && hamming > max_dist) c.Near("hamming <= (1 - delta) 256", max_dist, hamming, 0);
    }
    std::optional<double> p_prev;
    const std::optional<size_t> pp = prev_frame >= 0 ? t.FramePos(static_cast<int64_t>(prev_frame)) : std::nullopt;
    if (j >= 0 && pp) p_prev = FinalP(t, *pp, n.line, static_cast<int64_t>(j), static_cast<int>(kp));
    std::optional<double> p_landmark;
    if (!p_prev && landmark >= 0)
      p_landmark = n.line ? MapLineP(t, static_cast<int64_t>(landmark), at) : MapPointP(t, static_cast<int64_t>(landmark), at);
    const int expected_source = p_prev ? 0 : p_landmark ? 1 : 2;
    const double expected = p_prev ? *p_prev : p_landmark ? *p_landmark : p_init;
    c.Near("source", expected_source, source, 0);
    c.Near("before", expected, r.before, kTol);
    c.Near("after", expected, r.after, kTol);
  }

  // ---- cues ----
  // Sample pixels s, m, e of frame line `index` in frame group fp (its structure record).
  static bool SamplePixel(const TraceModel& t, size_t fp, int64_t index, int k, Eigen::Vector2d* px, Check& c) {
    const std::string id = "l" + std::to_string(t.frames()[fp].frame) + "." + std::to_string(index);
    const Record* s = nullptr;
    for (const RecordRef& ref : t.EntityRecords(id)) {
      const Record& r = t.At(ref);
      if (ref.frame_pos == fp && r.type == RecordType::kProbability && r.stage == "structure") s = &r;
    }
    if (s == nullptr) {
      c.Missing("structure record of " + id);
      return false;
    }
    const Eigen::Vector2d a(c.Need(*s, "x0"), c.Need(*s, "y0")), b(c.Need(*s, "x1"), c.Need(*s, "y1"));
    if (!c.ok()) return false;
    *px = k == 0 ? a : k == 2 ? b : Eigen::Vector2d(0.5 * (a + b));
    return true;
  }

  // The pixel pair (x^{k-1}, x^k) of a corresponded node; false (and unverifiable) when missing.
  bool PixelPair(const TraceModel& t, RecordRef at, const Node& n, size_t pp, int64_t j, int kp, Eigen::Vector2d* prev,
                 Eigen::Vector2d* cur, Check& c) const {
    if (n.line) return SamplePixel(t, pp, j, kp, prev, c) && SamplePixel(t, at.frame_pos, n.index, n.sample, cur, c);
    const Record* a = t.Obs(at.frame_pos, n.index);
    const Record* b = t.Obs(pp, j);
    if (a == nullptr || b == nullptr) {
      c.Missing(a == nullptr ? "OBS of the feature" : "OBS of the previous feature");
      return false;
    }
    *cur = Eigen::Vector2d(a->u, a->v), *prev = Eigen::Vector2d(b->u, b->v);
    return true;
  }

  struct Corr {
    const Record* frame = nullptr;
    const Record* inherit = nullptr;
    int64_t j = -1;
    int kp = 0;
    std::optional<size_t> pp;
  };
  bool Correspondence(const TraceModel& t, RecordRef at, const Node& n, Corr* out, Check& c) const {
    out->frame = FrameRecord(t, at.frame_pos);
    out->inherit = Find(t, at.frame_pos, n, "mgd.inherit");
    if (out->frame == nullptr) c.Missing("mgd.frame record of the frame");
    else if (out->inherit == nullptr) c.Missing("mgd.inherit record of " + t.At(at).entity);
    if (!c.ok()) return false;
    out->j = static_cast<int64_t>(c.Need(*out->inherit, "prev_index"));
    out->kp = n.line ? static_cast<int>(c.Need(*out->inherit, "prev_sample")) : 0;
    const double prev_frame = c.Need(*out->frame, "prev_frame");
    if (!c.ok()) return false;
    if (out->j >= 0) {
      out->pp = t.FramePos(static_cast<int64_t>(prev_frame));
      if (!out->pp) {
        c.Missing("frame " + std::to_string(static_cast<int64_t>(prev_frame)));
        return false;
      }
    }
    return true;
  }

  void VerifyLS(const TraceModel& t, RecordRef at, const Node& n, Check& c) const {
    const Record& r = t.At(at);
    Corr k;
    if (!Correspondence(t, at, n, &k, c)) return;
    const double computable = c.Need(r, "computable"), d = c.Need(r, "d_px"), dtheta = c.Need(r, "dtheta");
    const double n_vbar = c.Need(*k.frame, "n_vbar");
    const Eigen::Vector2d vbar(c.Need(*k.frame, "vbar_u"), c.Need(*k.frame, "vbar_v"));
    c.Near("vbar_u", vbar.x(), c.Need(r, "vbar_u"), kTol);  // the frame's mean flow (mgd.frame)
    c.Near("vbar_v", vbar.y(), c.Need(r, "vbar_v"), kTol);
    if (!c.ok()) return;
    if (n.line && params_.line_cue_form != "pseudo_point")
      return c.Missing("a verifier of line_cue_form '" + params_.line_cue_form + "' (README: pseudo_point only)");
    const bool expected_computable = k.j >= 0 && n_vbar > 0;
    c.Near("computable", expected_computable ? 1 : 0, computable, 0);
    if (!expected_computable) return c.Near("after", 0.5, r.after, kTol);
    Eigen::Vector2d prev, cur;
    if (!PixelPair(t, at, n, *k.pp, k.j, k.kp, &prev, &cur, c)) return;
    // v = x^k - x^{k-1}: float keypoints in the stage (difference in float), double line samples.
    Eigen::Vector2d v = cur - prev;
    if (!n.line)
      v = Eigen::Vector2d(static_cast<float>(cur.x()) - static_cast<float>(prev.x()),
                          static_cast<float>(cur.y()) - static_cast<float>(prev.y()));
    const Eigen::Vector2d res = v - vbar;
    const double e_d = std::sqrt(res.x() * res.x() + res.y() * res.y());
    double e_theta = 0;
    if (params_.angle_form == "literal_arctan") {
      e_theta = res.x() == 0 ? (res.y() == 0 ? 0.0 : std::copysign(M_PI / 2, res.y())) : std::atan(res.y() / res.x());
    } else {
      const double minv = Need(c, params_.min_velocity, "min_velocity_px");
      const double nv = std::sqrt(v.x() * v.x() + v.y() * v.y()), nb = std::sqrt(vbar.x() * vbar.x() + vbar.y() * vbar.y());
      if (nv >= minv && nb >= minv)
        e_theta = std::acos(std::min(1.0, std::max(-1.0, (v.x() * vbar.x() + v.y() * vbar.y()) / (nv * nb))));
    }
    const double a_ls = Need(c, params_.a_ls, "a_ls"), dth = Need(c, params_.d_th_ls, "d_th_ls_px");
    const double thth = Need(c, params_.theta_th, "theta_th_ls_rad");
    if (!c.ok()) return;
    c.Near("d_px", e_d, d, kTol);
    c.Near("dtheta", e_theta, dtheta, kTol);
    c.Near("after", Sig(a_ls * (e_d - dth) + (1.0 - a_ls) * (e_theta - thth)), r.after, kTol);
  }

  void VerifyMF(const TraceModel& t, RecordRef at, const Node& n, Check& c) const {
    const Record& r = t.At(at);
    Corr k;
    if (!Correspondence(t, at, n, &k, c)) return;
    const double computable = c.Need(r, "computable");
    const double d = c.Need(r, n.line ? "d_px" : "d_epi_px");
    const double has_F = c.Need(*k.frame, "has_F");
    if (!c.ok()) return;
    if (n.line && params_.line_cue_form != "pseudo_point")
      return c.Missing("a verifier of line_cue_form '" + params_.line_cue_form + "' (README: pseudo_point only)");
    const bool expected_computable = k.j >= 0 && has_F != 0;
    c.Near("computable", expected_computable ? 1 : 0, computable, 0);
    if (!expected_computable) return c.Near("after", 0.5, r.after, kTol);
    const std::optional<Eigen::Isometry3d> T = RelativePose(t, at.frame_pos, *k.frame, c);
    if (!T) return;
    const CameraModel& cam = t.camera();
    if (!cam.present) return c.Missing("header camera_json");
    Eigen::Vector2d prev, cur;
    if (!PixelPair(t, at, n, *k.pp, k.j, k.kp, &prev, &cur, c)) return;
    // F = K^-T [t]x R K^-1 (spec E9): the epipolar line of x^{k-1} in frame k is F x^{k-1}.
    Eigen::Matrix3d Kinv;
    Kinv << 1.0 / cam.fx, 0, -cam.cx / cam.fx, 0, 1.0 / cam.fy, -cam.cy / cam.fy, 0, 0, 1;
    const Eigen::Vector3d tt = T->translation();
    Eigen::Matrix3d tx;
    tx << 0, -tt.z(), tt.y(), tt.z(), 0, -tt.x(), -tt.y(), tt.x(), 0;
    const Eigen::Matrix3d F = Kinv.transpose() * tx * T->linear() * Kinv;
    const Eigen::Vector3d l = F * Eigen::Vector3d(prev.x(), prev.y(), 1.0);
    const double norm = std::sqrt(l.x() * l.x() + l.y() * l.y());
    const double e_d = norm == 0 ? std::numeric_limits<double>::infinity()
                                 : std::fabs(cur.x() * l.x() + cur.y() * l.y() + l.z()) / norm;
    const double a_mf = Need(c, params_.a_mf, "a_mf"), dth = Need(c, params_.d_th_mf, "d_th_mf_px");
    if (!c.ok()) return;
    c.Near(n.line ? "d_px" : "d_epi_px", e_d, d, kEpiTol);
    c.Near("after", Sig(a_mf * (e_d - dth)), r.after, kEpiTol);
  }

  void VerifyPro(const TraceModel& t, RecordRef at, const Node& n, Check& c) const {
    const Record& r = t.At(at);
    const double computable = c.Need(r, "computable");
    if (!c.ok()) return;
    if (n.line) {  // not computed for line samples (README): logit 0
      c.Near("computable", 0, computable, 0);
      return c.Near("after", 0.5, r.after, 0);
    }
    if (computable == 0) return c.Near("after", 0.5, r.after, 0);
    // The cue cached for the feature's map point: the latest mgd.reprojection record (before this
    // one) of the point it was computed for (source_mp: the feature's point, or one it replaced).
    const Record* inherit = Find(t, at.frame_pos, n, "mgd.inherit");
    if (inherit == nullptr) return c.Missing("mgd.inherit record of " + r.entity);
    const double mp = c.Need(*inherit, "map_point"), src = c.Need(r, "source_mp"), kf = c.Need(r, "kf");
    if (!c.ok()) return;
    if (mp < 0) return c.Near("map_point (P_pro needs one)", 0, mp, 0);
    const Record* cue = nullptr;
    for (const RecordRef& ref : t.EntityRecords("mp" + std::to_string(static_cast<int64_t>(src)))) {
      if (!Earlier(ref, at)) break;
      const Record& x = t.At(ref);
      if (x.type == RecordType::kProbability && x.stage == "mgd.reprojection") cue = &x;
    }
    if (cue == nullptr) return c.Missing("mgd.reprojection record of mp" + std::to_string(static_cast<int64_t>(src)));
    c.Near("kf", c.Need(*cue, "kf"), kf, 0);
    c.Near("covisible", c.Need(*cue, "covisible"), c.Need(r, "covisible"), 0);
    c.Near("mean_forward_px", c.Need(*cue, "mean_forward_px"), c.Need(r, "mean_forward_px"), kTol);
    c.Near("mean_backward_px", c.Need(*cue, "mean_backward_px"), c.Need(r, "mean_backward_px"), kTol);
    const double fwd = c.Need(r, "mean_forward_px"), bwd = c.Need(r, "mean_backward_px");
    const double a_pro = Need(c, params_.a_pro, "a_pro"), dth = Need(c, params_.d_th_pro, "d_th_pro_px");
    if (!c.ok()) return;
    c.Near("after", Sig(a_pro * (0.5 * (fwd + bwd) - dth)), r.after, kTol);
  }

  void VerifyReprojection(const Record& r, Check& c) const {
    int64_t id = -1;
    if (r.kind != EntityKind::kMapPoint || !ParseNumberId(r.entity, "mp", &id)) return c.Same("entity", "mp<id>", r.entity);
    const double cov = c.Need(r, "covisible"), with_depth = c.Need(r, "with_depth");
    const double fwd = c.Need(r, "mean_forward_px"), bwd = c.Need(r, "mean_backward_px");
    c.Need(r, "kf");
    const double a_pro = Need(c, params_.a_pro, "a_pro"), dth = Need(c, params_.d_th_pro, "d_th_pro_px");
    if (!c.ok()) return;
    c.Near("before", 0.5, r.before, 0);
    if (!(cov >= 1)) c.Near("covisible >= 1", 1, cov, 0);
    if (with_depth > cov || with_depth < 0) c.Near("with_depth <= covisible", cov, with_depth, 0);
    if (with_depth == 0) c.Near("mean_backward_px (no depth: the forward mean)", fwd, bwd, 0);
    c.Near("after", Sig(a_pro * (0.5 * (fwd + bwd) - dth)), r.after, kTol);
  }

  void VerifyFusion(const TraceModel& t, RecordRef at, const Node& n, Check& c) const {
    const Record& r = t.At(at);
    static const char* kCue[3] = {"mgd.P_LS", "mgd.P_pro", "mgd.P_mf"};
    static const char* kW[3] = {"w_ls", "w_pro", "w_mf"};
    const std::optional<double>* use[3] = {&params_.use_ls, &params_.use_pro, &params_.use_mf};
    const std::optional<double>* w[3] = {&params_.w_ls, &params_.w_pro, &params_.w_mf};
    double z = 0;
    for (int i = 0; i < 3; ++i) {
      const double wi = Need(c, *use[i], kW[i]) != 0 ? Need(c, *w[i], kW[i]) : 0.0;
      c.Near(kW[i], wi, c.Need(r, kW[i]), 0);
      const Record* cue = Find(t, at.frame_pos, n, kCue[i]);
      if (cue == nullptr) return c.Missing(std::string(kCue[i]) + " record of " + r.entity);
      z += wi * LogOdds(cue->after);
    }
    if (!c.ok()) return;
    c.Near("before", 0.5, r.before, 0);
    c.Near("after", Sig(z), r.after, kTol);
  }

  void VerifySmooth(const TraceModel& t, RecordRef at, const Node& n, Check& c) const {
    const Record& r = t.At(at);
    const Record* fusion = Find(t, at.frame_pos, n, "mgd.fusion");
    const Record* inherit = Find(t, at.frame_pos, n, "mgd.inherit");
    if (fusion == nullptr || inherit == nullptr)
      return c.Missing((fusion == nullptr ? "mgd.fusion" : "mgd.inherit") + std::string(" record of ") + r.entity);
    const double S = c.Need(r, "S"), a_in = c.Need(r, "a");
    const double a = Need(c, params_.a, "a");
    if (!c.ok()) return;
    c.Near("a", a, a_in, 0);
    c.Near("S", fusion->after, S, kTol);
    c.Near("before", inherit->after, r.before, kTol);
    const double P = params_.smoothing == "old_evidence" ? a * inherit->after + (1.0 - a) * fusion->after
                                                         : (1.0 - a) * inherit->after + a * fusion->after;
    c.Near("after", P, r.after, kTol);
  }

  // ---- mgd.diffuse: step 10 over every node of the frame ----
  const FrameIndex& Diffusion(const TraceModel& t, size_t fp, double radius) const {
    FrameIndex& fi = frames_[fp];
    Index(t, fp);
    if (fi.diffused) return fi;
    fi.diffused = true;
    // Nodes in the stage's order: features by index, then the 3 samples of each line.
    struct N {
      std::pair<int, std::pair<int64_t, int>> key;
      bool has = false;
      Eigen::Vector3d X;
      double p = 0;
    };
    std::vector<N> nodes;
    for (const auto& [key, idx] : fi.recs) {
      if (std::get<3>(key) != "mgd.diffuse") continue;
      const Record& r = t.frames()[fp].records[idx];
      N x;
      x.key = {std::get<0>(key), {std::get<1>(key), std::get<2>(key)}};
      x.has = Input(r, "has_point").value_or(0) != 0;
      x.X = Eigen::Vector3d(Input(r, "x").value_or(0), Input(r, "y").value_or(0), Input(r, "z").value_or(0));
      x.p = r.before;
      nodes.push_back(x);
    }
    const double r2 = radius * radius;
    for (const N& a : nodes) {
      double sum_w = 0, sum_wp = 0;
      int count = 0;
      if (a.has)
        for (const N& b : nodes) {
          if (&a == &b || !b.has) continue;
          const Eigen::Vector3d d = a.X - b.X;
          const double d2 = d.x() * d.x() + d.y() * d.y() + d.z() * d.z();
          if (d2 > r2) continue;
          const double w = std::exp(-std::sqrt(d2) / radius);  // lambda(d) = C exp(-d / r)
          sum_w += w;
          sum_wp += w * (b.p - a.p);
          ++count;
        }
      fi.diffusion[a.key] = {a.has ? a.p + sum_wp / (1.0 + sum_w) : a.p, count};  // C = 1 / (1 + sum exp)
    }
    return fi;
  }

  void VerifyDiffuse(const TraceModel& t, RecordRef at, const Node& n, Check& c) const {
    const Record& r = t.At(at);
    const Record* smooth = Find(t, at.frame_pos, n, "mgd.smooth");
    if (smooth == nullptr) return c.Missing("mgd.smooth record of " + r.entity);
    c.Near("before", smooth->after, r.before, kTol);
    const double neighbours = c.Need(r, "neighbours");
    const double on = Need(c, params_.diffusion, "diffusion"), tau = Need(c, params_.tau, "tau_dyn");
    if (!c.ok()) return;
    double expected = r.before;
    int count = 0;
    if (on != 0) {
      const double has = c.Need(r, "has_point"), x = c.Need(r, "x"), y = c.Need(r, "y"), z = c.Need(r, "z");
      const double radius = Need(c, params_.radius, "radius_m");
      if (!c.ok()) return;
      if (!n.line) {  // a feature's point: its OBS back-projected (u, v undistorted, depth)
        const Record* o = t.Obs(at.frame_pos, n.index);
        const CameraModel& cam = t.camera();
        if (o == nullptr) return c.Missing("OBS of " + r.entity);
        if (!cam.present) return c.Missing("header camera_json");
        c.Near("has_point", o->depth_m > 0 ? 1 : 0, has, 0);
        if (o->depth_m > 0) {
          c.Near("x", (o->u - cam.cx) * o->depth_m / cam.fx, x, kTol);
          c.Near("y", (o->v - cam.cy) * o->depth_m / cam.fy, y, kTol);
          c.Near("z", o->depth_m, z, kTol);
        }
      }
      const FrameIndex& fi = Diffusion(t, at.frame_pos, radius);
      const auto it = fi.diffusion.find({n.line ? 1 : 0, {n.index, n.line ? n.sample : -1}});
      if (it == fi.diffusion.end()) return c.Missing("diffusion node of " + r.entity);
      expected = it->second.first, count = it->second.second;
    }
    c.Near("neighbours", count, neighbours, 0);
    c.Near("after", expected, r.after, kTol);
    if (!n.line) c.Near("weight", r.after > tau ? 0.0 : KeptWeight(params_, r.after), c.Need(r, "weight"), kTol);
  }

  // ---- mgd.map_point: step 15 write-back ----
  void VerifyMapPoint(const TraceModel& t, RecordRef at, Check& c) const {
    const Record& r = t.At(at);
    int64_t mp = -1;
    if (r.kind != EntityKind::kMapPoint || !ParseNumberId(r.entity, "mp", &mp)) return c.Same("entity", "mp<id>", r.entity);
    const double feature = c.Need(r, "feature"), had_p = c.Need(r, "had_p");
    if (!c.ok()) return;
    const Record* d = Find(t, at.frame_pos, false, static_cast<int64_t>(feature), 0, "mgd.diffuse");
    const Record* inherit = Find(t, at.frame_pos, false, static_cast<int64_t>(feature), 0, "mgd.inherit");
    if (d == nullptr || inherit == nullptr) return c.Missing("mgd.diffuse / mgd.inherit of the feature");
    c.Near("map_point of the feature", static_cast<double>(mp), c.Need(*inherit, "map_point"), 0);
    const std::optional<double> old = MapPointP(t, mp, at);
    c.Near("had_p", old ? 1 : 0, had_p, 0);
    c.Near("after", d->after, r.after, kTol);
    c.Near("before", old ? *old : d->after, r.before, kTol);
  }

  // ---- mgd.line: step 11 ----
  void VerifyLine(const TraceModel& t, RecordRef at, const Node& n, Check& c) const {
    const Record& r = t.At(at);
    double before = 0, after = 0;
    for (int k = 0; k < 3; ++k) {
      const Record* d = Find(t, at.frame_pos, true, n.index, k, "mgd.diffuse");
      if (d == nullptr) return c.Missing("mgd.diffuse record of sample " + std::to_string(k));
      before = std::max(before, d->before), after = std::max(after, d->after);
      c.Near("map_line", c.Need(*d, "map_line"), c.Need(r, "map_line"), 0);
    }
    const double tau = Need(c, params_.tau, "tau_dyn"), w = c.Need(r, "weight");
    if (!c.ok()) return;
    c.Near("before", before, r.before, kTol);
    c.Near("after", after, r.after, kTol);
    c.Near("weight", after > tau ? 0.0 : KeptWeight(params_, after), w, kTol);
  }

  // ---- decisions: step 13 ----
  void VerifyDecision(const TraceModel& t, RecordRef at, Check& c) const {
    const Record& r = t.At(at);
    Node n;
    if (!ParseNode(r, &n)) return c.Same("entity", "f<frame>.<i> or l<frame>.<i>", r.entity);
    const double tau = Need(c, params_.tau, "tau_dyn");
    if (!c.ok()) return;
    if (r.stage == "mgd.boxes") {  // initialisation frame: P_init above tau_dyn
      const Record* b = n.line ? nullptr : Find(t, at.frame_pos, false, n.index, 0, "mgd.boxes");
      if (b == nullptr) return c.Missing("mgd.boxes record of " + r.entity);
      c.Same("reason", std::string("p-init>tau"), r.reason);
      c.Same("kept", false, r.kept);
      return c.Near("P_init > tau_dyn", 1, b->after > tau ? 1 : 0, 0);
    }
    if (n.line) {
      const Record* l = Find(t, at.frame_pos, true, n.index, -1, "mgd.line");
      if (l == nullptr) return c.Missing("mgd.line record of " + r.entity);
      const bool kept = c.Need(*l, "weight") > 0;
      c.Same("kept", kept, r.kept);
      return c.Same("reason", std::string(kept ? "max_p<=tau_dyn" : "max_p>tau_dyn"), r.reason);
    }
    const Record* d = Find(t, at.frame_pos, n, "mgd.diffuse");
    if (d == nullptr) return c.Missing("mgd.diffuse record of " + r.entity);
    const bool kept = !(d->after > tau);
    c.Same("kept", kept, r.kept);
    c.Same("reason", std::string(kept ? "p<=tau_dyn" : "p>tau_dyn"), r.reason);
  }
};

}  // namespace

void AddMgdVerifiers(VerifierList& out) { out.push_back(std::make_unique<MgdVerifier>()); }

}  // namespace dynref::verify
