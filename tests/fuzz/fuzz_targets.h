// Fuzz targets: the readers of every file a user hands dynref (issue 20). A target owns a work
// folder of valid files; an execution replaces ONE of them by a mutated copy of a seed, runs the
// reader(s) on the folder and restores the file.
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace dynref::fuzz {

struct Seed {
  std::string file;   // path relative to the work folder
  std::string bytes;  // valid content
};

struct Target {
  std::string name;
  std::string what;  // the readers it exercises
  // Writes the valid work folder and returns the seeds (each a file of that folder).
  std::function<std::vector<Seed>(const std::string& work)> setup;
  // Reads the folder; throws InputError for bad input (a clean rejection).
  std::function<void(const std::string& work)> run;
};

// stamped-list, trajectory, sequence, camera-yaml, method-yaml, mask-format, label-import, trace.
std::vector<Target> AllTargets();

}  // namespace dynref::fuzz
