// What a stage or map module leaves at the end of a run: the files it wrote into the run folder
// (reported in run.json "outputs") and, if it failed, its error (run.json "output_errors",
// end_state "error: ...", exit 2).
#pragma once
#include <string>
#include <vector>

namespace dynref {

struct RunOutput {
  std::string module;  // stage / map module name
  std::string path;    // as written (absolute or relative to the run folder)
  std::string what;    // one line: what the file holds
};

class RunEnd {
 public:
  explicit RunEnd(std::string out_dir) : out_dir_(std::move(out_dir)) {}
  // The run folder (empty when a stage is driven outside `dynref run`: write nothing then).
  const std::string& out_dir() const { return out_dir_; }
  void AddOutput(const std::string& module, const std::string& path, const std::string& what) {
    outputs_.push_back({module, path, what});
  }
  const std::vector<RunOutput>& outputs() const { return outputs_; }

 private:
  std::string out_dir_;
  std::vector<RunOutput> outputs_;
};

}  // namespace dynref
