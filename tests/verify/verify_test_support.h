// Shared by the verifier tests: run one family's verifiers over a trace file, and the report's
// examples as text for INFO().
#pragma once
#include <string>

#include "trace/trace_reader.h"
#include "verify/verifier.h"
#include "verify/verify_run.h"

namespace dynref::verify::test {

inline VerifyReport VerifyWith(const std::string& path, void (*add)(VerifierList&)) {
  trace::TraceReader reader(path);
  const TraceModel model(reader);
  VerifierList list;
  add(list);
  return VerifyTrace(model, list, {});
}

inline std::string Examples(const VerifyReport& r) {
  std::string s;
  for (const auto& [stage, st] : r.stages)
    for (const std::string& e : st.examples) s += stage + ": " + e + "\n";
  return s;
}

}  // namespace dynref::verify::test
