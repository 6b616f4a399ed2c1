#include "trace/trace_copy.h"

namespace dynref::trace {

void WriteRecord(TraceWriter& w, const Record& r) {
  switch (r.type) {
    case RecordType::kFrame: w.BeginFrame(static_cast<int>(r.frame), r.timestamp); break;
    case RecordType::kPose: {
      SE3 T = SE3::Identity();
      for (int i = 0; i < 12; ++i) T.matrix()(i / 4, i % 4) = r.T_wc[i];
      w.FramePose(r.name, T);
      break;
    }
    case RecordType::kCount: w.FrameCount(r.stage, r.name, r.value); break;
    case RecordType::kObservation:
      w.Observation(r.feature_index, r.map_point_id, r.associated_map_point_id, r.u, r.v, r.depth_m,
                    static_cast<int>(r.octave), r.descriptor_hash);
      break;
    case RecordType::kProbability: w.ProbabilityUpdate(r.stage, r.kind, r.entity, r.inputs, r.before, r.after); break;
    case RecordType::kResidual:
      w.Residual(r.stage, r.residual_kind, r.entity, r.residual_start, r.residual_end, r.information, r.weight,
                 r.robust_loss, r.chi2, r.inlier);
      break;
    case RecordType::kDecision: w.Decision(r.stage, r.kind, r.entity, r.kept, r.reason); break;
  }
}

RunHeader HeaderOf(const TraceReader& reader) {
  RunHeader h;
  for (const auto& [k, v] : reader.header()) {
    if (k == "dynref_version") h.dynref_version = v;
    else if (k == "dynref_commit") h.dynref_commit = v;
    else if (k == "method") h.method = v;
    else if (k == "config_json") h.config_json = v;
    else if (k == "sequence_path") h.sequence_path = v;
    else if (k == "detector_source") h.detector_source = v;
    else if (k == "detections_dir") h.detections_dir = v;
    else if (k.rfind("input_sha256:", 0) == 0) h.input_hashes.emplace_back(k.substr(13), v);
    else h.extra.emplace_back(k, v);
  }
  return h;
}

}  // namespace dynref::trace
