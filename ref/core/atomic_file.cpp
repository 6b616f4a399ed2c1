#include "core/atomic_file.h"
#include "core/error.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <system_error>
#include <stdexcept>

namespace dynref {

void EnsureDirectory(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (!std::filesystem::is_directory(dir))
    throw InputError(dir, "cannot create output directory" + (ec ? " (" + ec.message() + ")" : std::string()));
}

std::string TempPathFor(const std::string& path) {
  return path + ".tmp." + std::to_string(static_cast<long>(::getpid()));
}

void CheckDirectoryPath(const std::string& path, const std::string& option) {
  namespace fs = std::filesystem;
  for (fs::path p = path; !p.empty(); p = p.parent_path()) {
    std::error_code ec;
    if (fs::exists(p, ec)) {
      if (!fs::is_directory(p, ec)) throw InputError(option, p.string() + " exists and is not a directory");
      return;
    }
    if (p == p.parent_path()) return;
  }
}

std::string StagingDirectory::NormalisedTarget(const std::string& target) {
  namespace fs = std::filesystem;
  fs::path p = fs::absolute(fs::path(target)).lexically_normal();
  if (!p.has_filename() && p != p.root_path()) p = p.parent_path();  // "a/b/" -> "a/b"
  return p.string();
}

StagingDirectory::StagingDirectory(const std::string& target)
    : target_(NormalisedTarget(target)), dir_(TempPathFor(target_)) {
  namespace fs = std::filesystem;
  const fs::path parent = fs::path(target_).parent_path();
  for (fs::path p = parent; !p.empty() && !fs::exists(p); p = p.parent_path()) {
    created_parents_.insert(created_parents_.begin(), p.string());
    if (p == p.parent_path()) break;
  }
  if (!parent.empty()) EnsureDirectory(parent.string());
  std::error_code ec;
  fs::remove_all(dir_, ec);
  EnsureDirectory(dir_);
}

StagingDirectory::~StagingDirectory() {
  std::error_code ec;
  std::filesystem::remove_all(dir_, ec);
  if (!committed_)
    for (auto it = created_parents_.rbegin(); it != created_parents_.rend(); ++it)
      std::filesystem::remove(*it, ec);  // only succeeds when empty
}

void AtomicRename(const std::string& temp_path, const std::string& final_path) {
  if (std::rename(temp_path.c_str(), final_path.c_str()) != 0) {
    std::remove(temp_path.c_str());
    throw std::runtime_error("cannot rename " + temp_path + " to " + final_path);
  }
}

AtomicOutputFile::AtomicOutputFile(const std::string& final_path, bool binary)
    : final_path_(final_path), temp_path_(TempPathFor(final_path)) {
  out_.open(temp_path_, binary ? std::ios::out | std::ios::binary | std::ios::trunc
                               : std::ios::out | std::ios::trunc);
  if (!out_) throw std::runtime_error("cannot open " + temp_path_ + " for writing");
}

AtomicOutputFile::~AtomicOutputFile() {
  if (!committed_) {
    out_.close();
    std::remove(temp_path_.c_str());
  }
}

void AtomicOutputFile::Commit() {
  out_.flush();
  if (!out_) throw std::runtime_error("write failed: " + temp_path_);
  out_.close();
  AtomicRename(temp_path_, final_path_);
  committed_ = true;
}

void AtomicWriteFile(const std::string& path, const std::string& content) {
  AtomicOutputFile f(path, true);
  f.stream().write(content.data(), static_cast<std::streamsize>(content.size()));
  f.Commit();
}

}  // namespace dynref
