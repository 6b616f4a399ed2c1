// Diff: frames in ascending order; within a frame, golden records in file order, candidate
// records matched by key (type, stage, kind, entity, occurrence) so that another implementation
// may write a frame's records in a different order. An extra candidate record is placed right
// after the golden record matched by the candidate record preceding it.
#include "trace/trace_diff.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <unordered_map>

#include "core/error.h"
#include "core/format.h"
#include "trace/trace_dump.h"
#include "trace/trace_reader.h"
#include "trace/trace_source.h"

namespace dynref::trace {

void DiffOptions::Check() const {
  if (!(abs_tol >= 0)) throw InputError("--abs", "tolerance must be >= 0");
  if (!(rel_tol >= 0)) throw InputError("--rel", "tolerance must be >= 0");
  if (max_report < 1) throw InputError("--max-report", "must be >= 1");
  for (const auto& [k, v] : field_abs_tol)
    if (!(v >= 0)) throw InputError("--tol", "tolerance for " + k + " must be >= 0");
}

void DiffOptions::AddFieldTolerance(const std::string& spec) {
  const size_t eq = spec.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size())
    throw InputError("--tol", "expected FIELD=X, got '" + spec + "'");
  try {
    size_t used = 0;
    const double v = std::stod(spec.substr(eq + 1), &used);
    if (used != spec.size() - eq - 1) throw std::invalid_argument("trailing");
    field_abs_tol[spec.substr(0, eq)] = v;
  } catch (const std::logic_error&) {
    throw InputError("--tol", "bad number in '" + spec + "'");
  }
}

std::string Divergence::Describe() const {
  std::ostringstream s;
  s << "frame " << frame << ", stage " << (stage.empty() ? "-" : stage) << ", " << type;
  if (!entity_kind.empty()) s << " " << entity_kind;
  s << " " << (entity.empty() ? "-" : entity);
  if (occurrence) s << " (occurrence " << occurrence << ")";
  switch (kind) {
    case DivergenceKind::kMissing: s << ": MISSING in candidate"; break;
    case DivergenceKind::kExtra: s << ": EXTRA in candidate"; break;
    case DivergenceKind::kDiffer:
      s << ", field " << field << ": expected " << expected << ", actual " << actual
        << ", tolerance " << tolerance;
      break;
  }
  return s.str();
}

namespace {

std::string StageLabel(const FlatRecord& f) { return f.stage.empty() ? "(" + f.type + ")" : f.stage; }

std::string BaseName(const std::string& field) {
  const size_t b = field.find('[');
  return b == std::string::npos ? field : field.substr(0, b);
}

struct Tolerance {
  double abs, rel;
  std::string Text() const { return "abs=" + FormatDouble17(abs) + " rel=" + FormatDouble17(rel); }
};

Tolerance ToleranceFor(const DiffOptions& o, const std::string& field) {
  auto it = o.field_abs_tol.find(field);
  if (it == o.field_abs_tol.end()) it = o.field_abs_tol.find(BaseName(field));
  return {it != o.field_abs_tol.end() ? it->second : o.abs_tol, o.rel_tol};
}

bool FloatsAgree(double a, double b, const Tolerance& t) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  if (a == b) return true;  // includes equal infinities
  const double d = std::fabs(a - b);
  return d <= t.abs || d <= t.rel * std::max(std::fabs(a), std::fabs(b));
}

Divergence MakeDivergence(DivergenceKind kind, const FlatRecord& f, double position) {
  Divergence d;
  d.kind = kind;
  d.frame = f.frame;
  d.position = position;
  d.type = f.type;
  d.stage = f.stage;
  d.entity_kind = f.kind;
  d.entity = f.entity;
  d.occurrence = f.occurrence;
  return d;
}

// Compares the fields of a matched pair; fills the first differing field into d. Updates errors.
bool CompareFields(const FlatRecord& g, const FlatRecord& c, const DiffOptions& o,
                   std::map<std::string, FieldError>& errors, Divergence& d) {
  bool differs = false;
  auto note = [&](const std::string& field, std::string exp, std::string act, std::string tol) {
    if (differs) return;
    differs = true;
    d.field = field;
    d.expected = std::move(exp);
    d.actual = std::move(act);
    d.tolerance = std::move(tol);
  };
  std::unordered_map<std::string, const FlatField*> cand;
  for (const FlatField& x : c.fields) cand.emplace(x.name, &x);
  for (const FlatField& x : g.fields) {
    auto it = cand.find(x.name);
    if (it == cand.end()) {
      note(x.name, FieldText(x), "(absent)", "exact");
      continue;
    }
    const FlatField& y = *it->second;
    cand.erase(it);
    if (x.exact || y.exact) {
      if (x.exact != y.exact || x.text != y.text) note(x.name, FieldText(x), FieldText(y), "exact");
      continue;
    }
    const Tolerance t = ToleranceFor(o, x.name);
    FieldError& e = errors[x.name];
    ++e.compared;
    const double diff = std::fabs(x.number - y.number);
    if (std::isfinite(diff) && diff > 0) {
      const double rel = diff / std::max(std::fabs(x.number), std::fabs(y.number));
      if (diff > e.max_abs) {
        e.max_abs = diff;
        e.max_abs_frame = g.frame;
        e.max_abs_entity = g.entity.empty() ? StageLabel(g) : g.entity;
      }
      e.max_rel = std::max(e.max_rel, rel);
    }
    if (!FloatsAgree(x.number, y.number, t)) note(x.name, FieldText(x), FieldText(y), t.Text());
  }
  // Fields only the candidate has (in candidate order).
  for (const FlatField& y : c.fields)
    if (cand.count(y.name)) note(y.name, "(absent)", FieldText(y), "exact");
  return differs;
}

const FlatField* FindField(const FlatRecord& r, const std::string& name) {
  for (const FlatField& f : r.fields)
    if (f.name == name) return &f;
  return nullptr;
}

// The summary's measures of a matched pair (README "Diff", --summary).
void Measure(const FlatRecord& g, const FlatRecord& c, DiffResult& result) {
  if (g.type == "pose" && g.stage == "final") {
    double a[12], b[12];
    for (int i = 0; i < 12; ++i) {
      const std::string name = "T_wc[" + std::to_string(i) + "]";
      const FlatField* x = FindField(g, name);
      const FlatField* y = FindField(c, name);
      if (x == nullptr || y == nullptr || x->exact || y->exact) return;
      a[i] = x->number, b[i] = y->number;
    }
    // Rows r00 r01 r02 tx / r10 .. ty / r20 .. tz: translation at 3, 7, 11; the angle of
    // R_g^T R_c from its trace.
    const double dt = std::sqrt((a[3] - b[3]) * (a[3] - b[3]) + (a[7] - b[7]) * (a[7] - b[7]) + (a[11] - b[11]) * (a[11] - b[11]));
    double tr = 0;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) tr += a[4 * k + i] * b[4 * k + i];
    const double angle = std::acos(std::clamp((tr - 1) / 2, -1.0, 1.0)) * 180.0 / M_PI;
    result.pose_frames.push_back(g.frame);
    result.pose_trans_m.push_back(dt);
    result.pose_rot_deg.push_back(angle);
  } else if (g.type == "prob") {
    const FlatField* x = FindField(g, "after");
    const FlatField* y = FindField(c, "after");
    if (x != nullptr && y != nullptr && !x->exact && !y->exact)
      result.prob_after_diff[StageLabel(g)].push_back(std::fabs(x->number - y->number));
  }
}

// "n mean median p90 p99 max" of v (sorted in place).
std::string Distribution(std::vector<double> v, double scale = 1.0) {
  if (v.empty()) return "0,,,,,";
  std::sort(v.begin(), v.end());
  double sum = 0;
  for (double x : v) sum += x;
  const auto at = [&](double q) { return v[std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())))] * scale; };
  std::ostringstream s;
  s << v.size() << "," << FormatDouble17(sum / static_cast<double>(v.size()) * scale) << "," << FormatDouble17(at(0.5)) << ","
    << FormatDouble17(at(0.9)) << "," << FormatDouble17(at(0.99)) << "," << FormatDouble17(v.back() * scale);
  return s.str();
}

}  // namespace

DiffResult DiffTraces(const std::string& golden_path, const std::string& candidate_path,
                      const DiffOptions& options) {
  options.Check();
  TraceSource golden(golden_path);
  TraceSource candidate(candidate_path);
  DiffResult result;
  if (golden.level() != candidate.level())
    result.notes.push_back(std::string("trace levels differ: golden ") + LevelName(golden.level()) +
                           ", candidate " + LevelName(candidate.level()));
  if (golden.is_jsonl() || candidate.is_jsonl()) {
    result.notes.push_back("a JSONL trace has no header or footer: end state not compared");
  } else {
    for (const char* key : {"method", "sequence_path", "detector_source"})
      if (golden.HeaderValue(key) != candidate.HeaderValue(key))
        result.notes.push_back(std::string("header ") + key + " differs: golden '" +
                               golden.HeaderValue(key) + "', candidate '" +
                               candidate.HeaderValue(key) + "'");
    if (golden.end_state() != candidate.end_state()) {
      result.footer_differs = true;
      result.notes.push_back("end state differs: golden '" + golden.end_state() +
                             "', candidate '" + candidate.end_state() + "'");
    }
  }
  std::set<int64_t> frames;
  for (int64_t f : golden.Frames()) frames.insert(f);
  for (int64_t f : candidate.Frames()) frames.insert(f);

  for (int64_t frame : frames) {
    const std::vector<FlatRecord> g = golden.Frame(frame);
    const std::vector<FlatRecord> c = candidate.Frame(frame);
    std::unordered_map<std::string, size_t> gpos;
    for (size_t i = 0; i < g.size(); ++i) gpos.emplace(g[i].Key(), i);
    std::vector<long> match(g.size(), -1);  // golden index -> candidate index
    std::vector<Divergence> divs;
    double last_pos = -1;
    for (size_t j = 0; j < c.size(); ++j) {
      ++result.stages[StageLabel(c[j])].candidate;
      auto it = gpos.find(c[j].Key());
      if (it == gpos.end()) {
        divs.push_back(MakeDivergence(DivergenceKind::kExtra, c[j], last_pos + 0.5));
        ++result.stages[StageLabel(c[j])].extra;
      } else {
        match[it->second] = static_cast<long>(j);
        last_pos = static_cast<double>(it->second);
      }
    }
    for (size_t i = 0; i < g.size(); ++i) {
      StageCounts& sc = result.stages[StageLabel(g[i])];
      ++sc.golden;
      if (match[i] < 0) {
        divs.push_back(MakeDivergence(DivergenceKind::kMissing, g[i], static_cast<double>(i)));
        ++sc.missing;
        continue;
      }
      Measure(g[i], c[static_cast<size_t>(match[i])], result);
      Divergence d = MakeDivergence(DivergenceKind::kDiffer, g[i], static_cast<double>(i));
      if (CompareFields(g[i], c[match[i]], options, result.field_errors, d)) {
        divs.push_back(std::move(d));
        ++sc.differ;
      }
    }
    std::stable_sort(divs.begin(), divs.end(),
                     [](const Divergence& a, const Divergence& b) { return a.position < b.position; });
    result.total_divergences += divs.size();
    for (Divergence& d : divs) {
      if (result.divergences.size() >= static_cast<size_t>(options.max_report)) break;
      result.divergences.push_back(std::move(d));
    }
  }
  return result;
}

std::string DiffResult::Report(const std::string& golden, const std::string& candidate,
                               const DiffOptions& options) const {
  std::ostringstream s;
  s << "golden:    " << golden << "\ncandidate: " << candidate << "\n";
  s << "tolerance: abs=" << FormatDouble17(options.abs_tol)
    << " rel=" << FormatDouble17(options.rel_tol);
  for (const auto& [k, v] : options.field_abs_tol) s << " " << k << "=" << FormatDouble17(v);
  s << " (ids, labels, decisions exact)\n";
  for (const std::string& n : notes) s << "note: " << n << "\n";
  if (ExitCode() == 0) {
    s << "result: MATCH within tolerance\n";
  } else {
    uint64_t differ = 0, missing = 0, extra = 0;
    for (const auto& [k, c] : stages) differ += c.differ, missing += c.missing, extra += c.extra;
    s << "result: DIVERGED (" << differ << " records differ, " << missing << " missing, " << extra
      << " extra)\n";
    if (!divergences.empty()) {
      s << "first divergence: " << divergences.front().Describe() << "\n";
      s << "divergences in processing order (" << divergences.size() << " of " << total_divergences
        << "):\n";
      for (const Divergence& d : divergences) s << "  " << d.Describe() << "\n";
    }
  }
  s << "per stage:\n  stage,golden,candidate,differ,missing,extra\n";
  for (const auto& [k, c] : stages)
    s << "  " << CsvEscape(k) << "," << c.golden << "," << c.candidate << "," << c.differ << ","
      << c.missing << "," << c.extra << "\n";
  s << "largest error per float field (fields with a nonzero error):\n"
       "  field,compared,max_abs,max_rel,at_frame,at_entity\n";
  size_t exact_fields = 0;
  for (const auto& [k, e] : field_errors) {
    if (e.max_abs == 0) {
      ++exact_fields;
      continue;
    }
    s << "  " << CsvEscape(k) << "," << e.compared << "," << FormatDouble17(e.max_abs) << ","
      << FormatDouble17(e.max_rel) << "," << e.max_abs_frame << "," << CsvEscape(e.max_abs_entity)
      << "\n";
  }
  s << "  (" << exact_fields << " other float fields identical in every matched record)\n";
  if (options.summary) {
    s << "summary: final pose deviation over " << pose_frames.size() << " frames both runs tracked\n"
      << "  measure,frames,mean,median,p90,p99,max\n"
      << "  translation_mm," << Distribution(pose_trans_m, 1e3) << "\n"
      << "  rotation_deg," << Distribution(pose_rot_deg) << "\n";
    for (size_t i = 0; i < pose_frames.size(); ++i)
      if (pose_trans_m[i] > 1e-3) {
        s << "  first frame straying more than 1 mm: " << pose_frames[i] << " ("
          << FormatDouble17(pose_trans_m[i] * 1e3) << " mm)\n";
        break;
      }
    s << "summary: |after golden - after candidate| of the probability updates both runs made\n"
         "  stage,updates,mean,median,p90,p99,max\n";
    for (const auto& [stage, v] : prob_after_diff) s << "  " << CsvEscape(stage) << "," << Distribution(v) << "\n";
  }
  return s.str();
}

}  // namespace dynref::trace
