// Argument checks shared by the `dynref reproduce` tables: every argument is checked before
// anything is synthesised, run or written (InputError naming the option), so a typo in the last
// option does not cost minutes of work first.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace dynref::reproduce {

// Known synthetic presets, none twice; `allow_empty` for optional lists (a sweep that may be off).
void CheckPresetList(const std::vector<std::string>& presets, const std::string& option, bool allow_empty);
// The arguments every table with runs has: --frames (>= 30, or 0 = each preset's own length), --seeds, --detections, --sequences,
// and --collect without --reuse.
void CheckMatrixArgs(int frames, const std::vector<uint64_t>& seeds, const std::string& detections,
                     const std::vector<std::string>& sequences, bool reuse, bool collect);
// At least one seed, none twice.
void CheckSeedList(const std::vector<uint64_t>& seeds);
// ideal | yolo-like | sparseinst-like
void CheckDetectionMode(const std::string& mode);
// --out is a file path whose folder can be created, --work a folder path.
void CheckReportPaths(const std::string& out, const std::string& work);
// Once the arguments are checked: creates --out's folder and `work` (empty: none, e.g. --collect).
void MakeReportFolders(const std::string& out, const std::string& work);

}  // namespace dynref::reproduce
