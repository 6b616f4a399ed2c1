// `dynref enhance IMAGE|SEQ --out DIR`: seed 004 Module A on files, so that users can look at what
// feature extraction sees. A sequence folder: (alpha, p) tuned once on its first frame (as the
// epi.enhance stage), every RGB frame enhanced to DIR/<rgb stamp>.png; one image: DIR/<name>.png.
// DIR/enhance.txt lists the parameters and, per image, I_lo, I_hi, the fitness and the mean grey
// before and after. DIR is published whole (staged, renamed); an existing DIR is replaced only
// when it holds an enhance.txt written by dynref enhance.
#pragma once
#include <string>

#include "dynamic/epi/stages.h"

namespace dynref::epi {

struct EnhanceFilesResult {
  int images = 0;
  double alpha = 0, p = 0;
};

EnhanceFilesResult EnhanceFiles(const std::string& input, const std::string& out, const EnhanceStageOptions& options);

}  // namespace dynref::epi
