// Verifiers of loop closing's records (issue 34, ref/loop/README.md "Trace"; ORB-SLAM2, Mur-Artal
// & Tardos, T-RO 2017, Sec. V): the loop candidates' consistency verdicts, the geometric check of
// the accepted ones, the loop transform, and the essential-graph residuals. Written from the
// README's rules; never calls ref/loop. (The global BA's residuals are local-BA residuals of
// family "globalba": verify_backbone.cpp.)
#include <cmath>
#include <memory>
#include <string>

#include "verify/verifier.h"

namespace dynref::verify {
namespace {

using trace::Record;
using trace::RecordType;

// The last PROB of `stage` on `entity` before record `at` in its frame group (nullptr if none).
const Record* ProbBefore(const TraceModel& t, RecordRef at, const std::string& stage, const std::string& entity) {
  const auto& recs = t.frames()[at.frame_pos].records;
  for (size_t i = at.index; i-- > 0;) {
    const Record& r = recs[i];
    if (r.type == RecordType::kProbability && r.stage == stage && r.entity == entity) return &r;
  }
  return nullptr;
}

// PROB loop.candidate: accepted (after = 1) iff consistency >= threshold; its score passed the
// database's min_score; before = 0.
class CandidateProb final : public Verifier {
 public:
  bool Claims(const Record& r) const override { return r.type == RecordType::kProbability && r.stage == "loop.candidate"; }
  void Verify(const TraceModel& t, RecordRef at, Check& check) const override {
    const Record& r = t.At(at);
    const double consistency = check.Need(r, "consistency"), threshold = check.Need(r, "threshold");
    const double score = check.Need(r, "score"), min_score = check.Need(r, "min_score");
    check.Need(r, "query");
    if (!check.ok()) return;
    check.Near("before", 0, r.before, 0);
    check.Same("score >= min_score", true, score >= min_score);
    check.Near("after", consistency >= threshold ? 1 : 0, r.after, 0);
  }
};

// DECISION loop.candidate: kept = the PROB's verdict; reason consistent | not-consistent-enough
// (continues a group, below the threshold) | new-group (continues none).
class CandidateDecision final : public Verifier {
 public:
  bool Claims(const Record& r) const override { return r.type == RecordType::kDecision && r.stage == "loop.candidate"; }
  void Verify(const TraceModel& t, RecordRef at, Check& check) const override {
    const Record& r = t.At(at);
    const Record* p = ProbBefore(t, at, "loop.candidate", r.entity);
    if (p == nullptr) return check.Missing("PROB loop.candidate " + r.entity);
    const double consistency = check.Need(*p, "consistency");
    if (!check.ok()) return;
    const bool kept = p->after == 1;
    check.Same("kept", kept, r.kept);
    check.Same("reason", kept ? "consistent" : consistency > 0 ? "not-consistent-enough" : "new-group", r.reason);
  }
};

// PROB loop.geometry: after = 1 iff bow_matches >= bow_min, se3_inliers >= se3_min and
// loop_matches >= loop_min.
class GeometryProb final : public Verifier {
 public:
  bool Claims(const Record& r) const override { return r.type == RecordType::kProbability && r.stage == "loop.geometry"; }
  void Verify(const TraceModel& t, RecordRef at, Check& check) const override {
    const Record& r = t.At(at);
    const double bow = check.Need(r, "bow_matches"), bow_min = check.Need(r, "bow_min");
    const double se3 = check.Need(r, "se3_inliers"), se3_min = check.Need(r, "se3_min");
    const double loop = check.Need(r, "loop_matches"), loop_min = check.Need(r, "loop_min");
    check.Need(r, "query");
    if (!check.ok()) return;
    check.Near("before", 0, r.before, 0);
    check.Near("after", bow >= bow_min && se3 >= se3_min && loop >= loop_min ? 1 : 0, r.after, 0);
  }
};

// DECISION loop.geometry: kept = the PROB's verdict; the reason names the first failed test.
class GeometryDecision final : public Verifier {
 public:
  bool Claims(const Record& r) const override { return r.type == RecordType::kDecision && r.stage == "loop.geometry"; }
  void Verify(const TraceModel& t, RecordRef at, Check& check) const override {
    const Record& r = t.At(at);
    const Record* p = ProbBefore(t, at, "loop.geometry", r.entity);
    if (p == nullptr) return check.Missing("PROB loop.geometry " + r.entity);
    const double bow = check.Need(*p, "bow_matches"), bow_min = check.Need(*p, "bow_min");
    const double se3 = check.Need(*p, "se3_inliers"), se3_min = check.Need(*p, "se3_min");
    if (!check.ok()) return;
    const bool kept = p->after == 1;
    check.Same("kept", kept, r.kept);
    std::string reason = kept ? "loop" : bow < bow_min ? "few-bow-matches" : se3 < se3_min ? "ransac-failed" : "few-loop-matches";
    if (!kept && bow == 0 && r.reason == "bad-keyframe") reason = r.reason;  // no vectors to match
    check.Same("reason", reason, r.reason);
  }
};

// PROB loop.transform on the closing keyframe: p 0 -> 0, a unit quaternion, and the accepted
// loop.geometry record of its loop keyframe for this query earlier in the frame.
class TransformProb final : public Verifier {
 public:
  bool Claims(const Record& r) const override { return r.type == RecordType::kProbability && r.stage == "loop.transform"; }
  void Verify(const TraceModel& t, RecordRef at, Check& check) const override {
    const Record& r = t.At(at);
    const double loop_kf = check.Need(r, "loop_kf");
    const double qx = check.Need(r, "qx"), qy = check.Need(r, "qy"), qz = check.Need(r, "qz"), qw = check.Need(r, "qw");
    check.Need(r, "tx"), check.Need(r, "ty"), check.Need(r, "tz"), check.Need(r, "moved_m");
    if (!check.ok()) return;
    check.Near("before", 0, r.before, 0);
    check.Near("after", 0, r.after, 0);
    check.Near("|q|", 1.0, std::sqrt(qx * qx + qy * qy + qz * qz + qw * qw), 1e-9);
    const std::string loop_entity = "kf" + std::to_string(static_cast<int64_t>(loop_kf));
    const Record* g = ProbBefore(t, at, "loop.geometry", loop_entity);
    if (g == nullptr) return check.Missing("PROB loop.geometry " + loop_entity);
    check.Near("loop.geometry after", 1, g->after, 0);
    int64_t query = -1;
    ParseNumberId(r.entity, "kf", &query);
    check.Near("loop.geometry query", static_cast<double>(query), Input(*g, "query").value_or(-1), 0);
  }
};

// RESIDUAL essential#N: kind se3edge6, 6-vectors, identity information, weight 1, no robust
// kernel: chi2 = robust_loss = |residual_end|^2, always an inlier.
class EssentialResidual final : public Verifier {
 public:
  bool Claims(const Record& r) const override {
    return r.type == RecordType::kResidual && r.stage.rfind("essential#", 0) == 0;
  }
  void Verify(const TraceModel& t, RecordRef at, Check& check) const override {
    const Record& r = t.At(at);
    check.Same("residual_kind", "se3edge6", r.residual_kind);
    check.Near("residual_start size", 6, static_cast<double>(r.residual_start.size()), 0);
    check.Near("residual_end size", 6, static_cast<double>(r.residual_end.size()), 0);
    if (!check.ok()) return;
    double sq = 0;
    for (double e : r.residual_end) sq += e * e;
    check.Near("information", 1, r.information, 0);
    check.Near("weight", 1, r.weight, 0);
    check.Near("chi2", sq, r.chi2);
    check.Near("robust_loss", sq, r.robust_loss);
    check.Same("inlier", true, r.inlier);
    int64_t a = -1, b = -1;
    const size_t dash = r.entity.find('-');
    const bool ok = dash != std::string::npos && ParseNumberId(r.entity.substr(0, dash), "kf", &a) &&
                    ParseNumberId(r.entity.substr(dash + 1), "kf", &b);
    check.Same("observation id", true, ok);
  }
};

}  // namespace

void AddLoopVerifiers(VerifierList& out) {
  out.push_back(std::make_unique<CandidateProb>());
  out.push_back(std::make_unique<CandidateDecision>());
  out.push_back(std::make_unique<GeometryProb>());
  out.push_back(std::make_unique<GeometryDecision>());
  out.push_back(std::make_unique<TransformProb>());
  out.push_back(std::make_unique<EssentialResidual>());
}

}  // namespace dynref::verify
