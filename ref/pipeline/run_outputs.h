// The files of a finished run (pipeline.h lists them): trajectory.txt, keyframes.txt, lost.txt
// and run.json, each written atomically.
#pragma once
#include <string>

#include "method/session.h"
#include "pipeline/frame_loop.h"
#include "pipeline/run_inputs.h"

namespace dynref {

// trajectory.txt (ORB-SLAM2 SaveTrajectoryTUM), keyframes.txt, lost.txt; fills result counts.
void WriteTrajectoryFiles(const std::string& out_dir, const RunInputs& inputs, FrameLoop& loop);
// run.json into dir; `end` holds the outputs and errors of the method's components.
void WriteRunJson(const RunOptions& options, const RunInputs& inputs, FrameLoop& loop, const SessionEnd& end,
                  const std::string& dir);

// Where a run folder is published (issue 37): `target`, except that a failed run (exit code != 0)
// never replaces a published run (target has a run.json): it goes to "<target>.failed" instead,
// and stderr says that `shown` keeps its earlier run and where the failed attempt is.
std::string FailedRunTarget(const std::string& target, const std::string& shown, const RunResult& result);

}  // namespace dynref
