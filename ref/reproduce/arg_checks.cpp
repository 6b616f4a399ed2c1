#include "reproduce/arg_checks.h"

#include <algorithm>
#include <filesystem>
#include <set>

#include "core/atomic_file.h"
#include "core/error.h"
#include <string>
#include "synth/world.h"

namespace fs = std::filesystem;

namespace dynref::reproduce {

void CheckPresetList(const std::vector<std::string>& presets, const std::string& option, bool allow_empty) {
  if (presets.empty() && !allow_empty) throw InputError(option, "no presets given");
  const std::vector<std::string> known = synth::PresetNames();
  std::string list;
  for (const auto& n : known) list += (list.empty() ? "" : ", ") + n;
  std::set<std::string> seen;
  for (const std::string& p : presets) {
    if (std::find(known.begin(), known.end(), p) == known.end())
      throw InputError(option, "unknown preset '" + p + "' (known: " + list +
                                   (allow_empty ? "; or 'none' alone to skip" : "") + ")");
    if (!seen.insert(p).second) throw InputError(option, "preset '" + p + "' given twice");
  }
}

void CheckMatrixArgs(int frames, const std::vector<uint64_t>& seeds, const std::string& detections,
                     const std::vector<std::string>& sequences, bool reuse, bool collect) {
  if (frames != 0 && frames < 30)
    throw InputError("--frames", "need at least 30 frames, got " + std::to_string(frames) + " (or 0: each preset's own length)");
  CheckSeedList(seeds);
  CheckDetectionMode(detections);
  CheckPresetList(sequences, "--sequences", false);
  if (collect && reuse) throw InputError("--collect", "--collect only reads; --reuse has no meaning with it");
}

void CheckSeedList(const std::vector<uint64_t>& seeds) {
  if (seeds.empty()) throw InputError("--seeds", "no seed given");
  if (std::set<uint64_t>(seeds.begin(), seeds.end()).size() != seeds.size())
    throw InputError("--seeds", "a seed is given twice");
}

void CheckDetectionMode(const std::string& mode) {
  const std::vector<std::string> modes = {"ideal", "yolo-like", "sparseinst-like"};
  if (std::find(modes.begin(), modes.end(), mode) == modes.end())
    throw InputError("--detections", "unknown detection mode '" + mode + "' (known: ideal, yolo-like, sparseinst-like)");
}

void CheckReportPaths(const std::string& out, const std::string& work) {
  if (out.empty()) throw InputError("--out", "empty report path");
  if (work.empty()) throw InputError("--work", "empty folder path");
  std::error_code ec;
  if (fs::is_directory(out, ec)) throw InputError("--out", out + " is a directory (give the report's file name)");
  CheckDirectoryPath(fs::path(out).parent_path().string(), "--out");
  CheckDirectoryPath(work, "--work");
}

void MakeReportFolders(const std::string& out, const std::string& work) {
  const fs::path report_dir = fs::path(out).parent_path();
  if (!report_dir.empty()) fs::create_directories(report_dir);
  if (!work.empty()) fs::create_directories(work);
}

}  // namespace dynref::reproduce
