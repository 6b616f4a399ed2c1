// Verifiers of the semantic records (ref/verify/README.md, section "Semantic mapping"). Written
// from seed 002 (spec 002 steps 2-5) and ref/dynamic/semantic/README.md; never calls the stage.
//   semantic.interaction  Sec. 3.2: B (prior static) interacts with A (prior dynamic) iff |Q| > 0
//                         and mean |Z(a) - Z(b)| < T_int; B's tests run in ascending A and stop
//                         at the first hit.
//   semantic.mask         Sec. 3.1 Table 1: prior dynamic = class in the list and conf >= min;
//                         M_dyn = prior dynamic + non-prior dynamic; keypoints in M_dyn removed.
#include <functional>
#include <set>

#include "io/coco_classes.h"
#include "verify/verifier.h"

namespace dynref::verify {
namespace {

using trace::Record;
using trace::RecordType;

constexpr const char* kSemanticMask = "semantic.mask";
constexpr const char* kInteraction = "semantic.interaction";

// PROB records of `stage` on `entity` in frame group `frame_pos` (before record `before`), in order.
std::vector<const Record*> ProbsInFrame(const TraceModel& t, size_t frame_pos, const std::string& stage,
                                        const std::string& entity, size_t before = std::string::npos) {
  std::vector<const Record*> out;
  for (const RecordRef& ref : t.EntityRecords(entity)) {
    if (ref.frame_pos != frame_pos || ref.index >= before) continue;
    const Record& r = t.At(ref);
    if (r.type == RecordType::kProbability && r.stage == stage) out.push_back(&r);
  }
  return out;
}
const Record* LastProb(const TraceModel& t, size_t frame_pos, const std::string& stage, const std::string& entity,
                       size_t before = std::string::npos) {
  const std::vector<const Record*> all = ProbsInFrame(t, frame_pos, stage, entity, before);
  return all.empty() ? nullptr : all.back();
}

std::string Param(const TraceModel& t, const std::string& key) {
  std::string v;
  t.StageParam(kSemanticMask, key, &v);
  return v;
}

std::set<int> PriorDynamicIds(const TraceModel& t) { return t.StageClassIds(kSemanticMask, "prior_dynamic_classes"); }

// Table 1 partition of one instance from its semantic.mask instance record.
struct Partition {
  bool classified = false;  // conf >= min_confidence and a class
  bool prior_dynamic = false;
  int class_id = -1;
};
Partition Classify(const TraceModel& t, const Record& r, Check& c) {
  Partition p;
  const double class_id = c.Need(r, "class_id"), conf = c.Need(r, "confidence");
  const double min_conf = AppliedMinConfidence(t, r, kSemanticMask, c);
  const std::set<int> prior = PriorDynamicIds(t);
  if (prior.empty()) c.Missing("config semantic.mask.prior_dynamic_classes");
  if (!c.ok()) return p;
  p.class_id = static_cast<int>(class_id);
  p.classified = conf >= min_conf && p.class_id >= 0;
  p.prior_dynamic = p.classified && prior.count(p.class_id) > 0;
  return p;
}

// The partition of instance `inst` of this frame (from its record; Missing when absent).
bool InstancePartition(const TraceModel& t, size_t frame_pos, int64_t inst, Partition* p, Check& c) {
  const std::string id = "i" + std::to_string(t.frames()[frame_pos].frame) + "." + std::to_string(inst);
  const Record* r = LastProb(t, frame_pos, kSemanticMask, id);
  if (r == nullptr) {
    c.Missing("semantic.mask record of " + id);
    return false;
  }
  *p = Classify(t, *r, c);
  return c.ok();
}

// Whether the instance record's entity became non-prior dynamic: an interaction record with
// after = 1 in this frame (that record is verified on its own).
bool NonPriorDynamic(const TraceModel& t, size_t frame_pos, const std::string& entity) {
  for (const Record* r : ProbsInFrame(t, frame_pos, kInteraction, entity))
    if (r->after == 1) return true;
  return false;
}

void VerifyInteraction(const TraceModel& t, RecordRef at, Check& c) {
  const Record& r = t.At(at);
  int64_t frame = 0, b = 0;
  if (!ParseDottedId(r.entity, "i", &frame, &b)) return c.Same("entity", std::string("i<frame>.<inst>"), r.entity);
  const double a = c.Need(r, "with_instance"), pairs = c.Need(r, "pairs"), dz = c.Need(r, "dz_mean_m");
  const double t_int = c.Need(r, "t_int_m"), d_max = c.Need(r, "d_max_px");
  const double t_int_cfg = c.Need(t.StageNumber(kSemanticMask, "t_int_m"), "config semantic.mask.t_int_m");
  const double d_max_cfg = c.Need(t.StageNumber(kSemanticMask, "d_max_px"), "config semantic.mask.d_max_px");
  if (!c.ok()) return;
  c.Same("config semantic.mask.interaction", std::string("true"), Param(t, "interaction"));
  c.Near("t_int_m", t_int_cfg, t_int, 0);
  c.Near("d_max_px", d_max_cfg, d_max, 0);
  c.Near("before", 0, r.before, 0);
  // Only tests with pixel pairs are recorded (no pair: not adjacent, no test).
  c.Same("pairs > 0", true, pairs > 0);
  c.Same("dz_mean_m >= 0", true, dz >= 0);
  // A is prior dynamic, B prior static (Table 1).
  Partition pa, pb;
  if (!InstancePartition(t, at.frame_pos, static_cast<int64_t>(a), &pa, c)) return;
  if (!InstancePartition(t, at.frame_pos, b, &pb, c)) return;
  c.Same("with_instance prior dynamic", true, pa.prior_dynamic);
  c.Same("instance prior static", true, pb.classified && !pb.prior_dynamic);
  // B's tests: ascending A, none after the first hit.
  for (const Record* e : ProbsInFrame(t, at.frame_pos, kInteraction, r.entity, at.index)) {
    c.Same("earlier test of " + r.entity + " hit", false, e->after == 1);
    c.Same("with_instance ascending", true, Input(*e, "with_instance").value_or(-1) < a);
  }
  // spec 002 step 3.4: interacting iff |Q| > 0 and dz_mean < T_int.
  if (Agrees(dz, t_int_cfg, kTol)) return;  // too close to T_int to tell: either answer
  c.Near("after", pairs > 0 && dz < t_int_cfg ? 1 : 0, r.after, 0);
}

void VerifySemanticMaskProb(const TraceModel& t, RecordRef at, Check& c) {
  const Record& r = t.At(at);
  c.Near("before", 0, r.before, 0);
  if (r.kind == trace::EntityKind::kInstanceMask) {
    const Partition p = Classify(t, r, c);
    if (!c.ok()) return;
    const bool non_prior = p.classified && !p.prior_dynamic && NonPriorDynamic(t, at.frame_pos, r.entity);
    c.Near("after", p.prior_dynamic || non_prior ? 1 : 0, r.after, 0);
    return;
  }
  // A removed keypoint: the instance of M_dyn at it.
  const double inst = c.Need(r, "instance");
  if (!c.ok()) return;
  c.Same("config semantic.mask.reject_keypoints", std::string("true"), Param(t, "reject_keypoints"));
  c.Same("instance != 0", true, inst != 0);
  const std::string id = "i" + std::to_string(t.frames()[at.frame_pos].frame) + "." +
                         std::to_string(static_cast<int64_t>(inst));
  const Record* ir = LastProb(t, at.frame_pos, kSemanticMask, id);
  if (ir == nullptr) return c.Missing("semantic.mask record of " + id);
  c.Near("instance in M_dyn (semantic.mask " + id + " after)", 1, ir->after, 0);
  c.Near("after", 1, r.after, 0);
}

void VerifySemanticMaskDecision(const TraceModel& t, RecordRef at, Check& c) {
  const Record& r = t.At(at);
  const Record* p = LastProb(t, at.frame_pos, kSemanticMask, r.entity, at.index);
  if (p == nullptr) return c.Missing("semantic.mask PROB of " + r.entity);
  if (r.kind == trace::EntityKind::kInstanceMask) {
    const Partition part = Classify(t, *p, c);
    if (!c.ok()) return;
    c.Same("classified (conf >= min_confidence, a class)", true, part.classified);
    const bool non_prior = !part.prior_dynamic && NonPriorDynamic(t, at.frame_pos, r.entity);
    const bool dyn = part.prior_dynamic || non_prior;
    const std::string name = CocoClassName(part.class_id);
    c.Same("kept", !dyn, r.kept);
    c.Same("reason",
           part.prior_dynamic ? "prior-dynamic:" + name : non_prior ? "non-prior-dynamic:" + name : "static:" + name,
           r.reason);
    return;
  }
  const double inst = c.Need(*p, "instance");
  if (!c.ok()) return;
  c.Same("kept", inst == 0, r.kept);
  c.Same("reason", std::string("dynamic-mask"), r.reason);
}

}  // namespace

void AddSemanticVerifiers(VerifierList& out) {
  auto add = [&](RecordType type, const char* stage, StageVerifier::Fn fn) {
    out.push_back(std::make_unique<StageVerifier>(type, stage, std::move(fn)));
  };
  add(RecordType::kProbability, kInteraction, VerifyInteraction);
  add(RecordType::kProbability, kSemanticMask, VerifySemanticMaskProb);
  add(RecordType::kDecision, kSemanticMask, VerifySemanticMaskDecision);
}

}  // namespace dynref::verify
