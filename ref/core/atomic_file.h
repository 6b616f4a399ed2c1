// Outputs are written to a temporary file next to the target and renamed on success,
// so a failed or interrupted run never leaves a half-written result under the final name.
#pragma once
#include <fstream>
#include <string>
#include <vector>

namespace dynref {

class AtomicOutputFile {
 public:
  explicit AtomicOutputFile(const std::string& final_path, bool binary = false);
  ~AtomicOutputFile();  // removes the temp file unless Commit() succeeded
  AtomicOutputFile(const AtomicOutputFile&) = delete;
  AtomicOutputFile& operator=(const AtomicOutputFile&) = delete;

  std::ostream& stream() { return out_; }
  const std::string& temp_path() const { return temp_path_; }
  // Flushes, closes and renames to the final path. Throws std::runtime_error on failure.
  void Commit();

 private:
  std::string final_path_;
  std::string temp_path_;
  std::ofstream out_;
  bool committed_ = false;
};

// Writes a whole text/binary blob atomically.
void AtomicWriteFile(const std::string& path, const std::string& content);

// Renames an already written temp file onto path (same directory), throwing on failure.
void AtomicRename(const std::string& temp_path, const std::string& final_path);

// Creates dir and its missing parents (mkdir -p); InputError naming dir when that fails or
// a non-directory is in the way.
void EnsureDirectory(const std::string& dir);

// Temp name used for path: "<path>.tmp.<pid>".
std::string TempPathFor(const std::string& path);

// InputError(option, "<p> exists and is not a directory") when `path`, or its nearest existing
// ancestor if `path` does not exist yet, is not a directory (so creating it would fail).
void CheckDirectoryPath(const std::string& path, const std::string& option);

// A folder of outputs that must appear complete or not at all: they are written into the temp
// sibling dir() = "<target>.tmp.<pid>" and moved onto target() (absolute, normalised, no
// trailing separator) by the caller. The constructor creates target's missing parents and a
// fresh dir() (a stale one of a dead process with our pid is removed). The destructor removes
// dir(); unless Commit() was called it also removes the parents it created (when empty).
class StagingDirectory {
 public:
  explicit StagingDirectory(const std::string& target);
  ~StagingDirectory();
  StagingDirectory(const StagingDirectory&) = delete;
  StagingDirectory& operator=(const StagingDirectory&) = delete;

  const std::string& target() const { return target_; }
  const std::string& dir() const { return dir_; }
  void Commit() { committed_ = true; }

  // target as StagingDirectory normalises it (callers may check it before staging).
  static std::string NormalisedTarget(const std::string& target);

 private:
  std::string target_, dir_;
  std::vector<std::string> created_parents_;  // outermost first
  bool committed_ = false;
};

// Moves a finished staging folder onto target, replacing what is there (the previous output is
// renamed aside first and put back if the move fails, then removed). `replaceable(target)` is
// asked again right before the move (something may have appeared meanwhile); false gives
// InputError(shown, refusal). std::filesystem_error names the paths on an I/O failure.
void PublishDirectory(const std::string& staged, const std::string& target, const std::string& shown,
                      bool (*replaceable)(const std::string& dir), const std::string& refusal);

// True when path does not exist or is an empty directory.
bool IsAbsentOrEmptyDirectory(const std::string& path);

// Removes "<target>.tmp.<pid>" siblings (staging folders and temp files) whose process is no
// longer alive (a killed run); returns the removed paths. Never touches a live process's.
std::vector<std::string> RemoveStaleTemps(const std::string& target);

// An advisory exclusive lock (flock) on "<target>.lock", held until destruction, so that two
// processes never write the same output folder: InputError(option, "... is being written by
// another dynref process ...") at once when it is held. The lock file is removed on release.
class OutputLock {
 public:
  OutputLock(const std::string& target, const std::string& option);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace dynref
