// Outputs are written to a temporary file next to the target and renamed on success,
// so a failed or interrupted run never leaves a half-written result under the final name.
#pragma once
#include <fstream>
#include <string>

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

}  // namespace dynref
