// Off-screen plot for `dynref trace feature --plot`: dynamic probability vs frame.
#pragma once
#include <string>

#include "render/canvas.h"
#include "trace/trace_feature.h"

namespace dynref::render {

// Every ProbabilityUpdate in the history as a point (value after the update) joined per entity;
// the marker colour names the stage that made the jump (legend), decisions are marked under the
// axis (green triangle kept, red cross rejected).
Canvas RenderFeaturePlot(const trace::FeatureHistory& history);
void WriteFeaturePlot(const trace::FeatureHistory& history, const std::string& png_path);

}  // namespace dynref::render
