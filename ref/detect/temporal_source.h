// A detection source whose frames pass through a TemporalLinker (temporal_links.h), so
// `dynref run --detector SPEC --detector-temporal-gap N` sees the same carried person boxes as
// `dynref detect --temporal-gap N` written to a folder (issue 39 item 3). Frames must be given in
// sequence order (the run's frame loop does); name() and model_sha256() are the inner source's,
// so the score calibration (score_calibration.h) still keys on the detector that made the scores.
#pragma once
#include <memory>
#include <opencv2/core.hpp>

#include "detect/detection_source.h"
#include "detect/temporal_links.h"

namespace dynref::detect {

// options.max_gap == 0 returns inner unchanged. std::invalid_argument for bad options.
std::unique_ptr<DetectionSource> WithTemporalLinks(std::unique_ptr<DetectionSource> inner,
                                                   const TemporalOptions& options, cv::Size image_size);

}  // namespace dynref::detect
