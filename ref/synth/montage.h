// Montage PNG of a few frames of one or more `dynref synth` folders with the ground truth drawn
// over the RGB: people tinted per instance, moving pixels (gt/motion) outlined red, other
// labelled objects outlined yellow; one depth tile per row. For a person to look at.
#pragma once
#include <string>
#include <vector>

namespace dynref::synth {

struct MontageOptions {
  int frames_per_row = 3;
  int tile_width = 256;   // tiles keep the 4:3 aspect
  void Check() const;
};

void WriteMontage(const std::vector<std::string>& sequence_dirs, const std::string& out_png,
                  const MontageOptions& options = {});

}  // namespace dynref::synth
