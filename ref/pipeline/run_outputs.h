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

}  // namespace dynref
