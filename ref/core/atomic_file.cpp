#include "core/atomic_file.h"
#include "core/error.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>

#include <algorithm>
#include <cstdio>
#include <cstring>
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
  if (out_.fail()) throw std::runtime_error("write failed (close): " + temp_path_);  // e.g. disk full
  AtomicRename(temp_path_, final_path_);
  committed_ = true;
}

void AtomicWriteFile(const std::string& path, const std::string& content) {
  AtomicOutputFile f(path, true);
  f.stream().write(content.data(), static_cast<std::streamsize>(content.size()));
  f.Commit();
}

bool IsAbsentOrEmptyDirectory(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(path, ec))) return true;
  return fs::is_directory(path, ec) && fs::is_empty(path, ec) && !ec;
}

void PublishDirectory(const std::string& staged, const std::string& target, const std::string& shown,
                      bool (*replaceable)(const std::string& dir), const std::string& refusal) {
  namespace fs = std::filesystem;
  if (!replaceable(target)) throw InputError(shown, refusal);
  std::error_code ec;
  const bool had_old = fs::exists(fs::symlink_status(target, ec));
  const fs::path old = TempPathFor(target) + ".old";
  if (had_old) {
    fs::remove_all(old, ec);
    fs::rename(target, old);  // throws filesystem_error naming the paths
  }
  try {
    fs::rename(staged, target);
  } catch (...) {
    if (had_old) fs::rename(old, target, ec);  // put the previous output back
    throw;
  }
  if (had_old) fs::remove_all(old, ec);
}

std::vector<std::string> RemoveStaleTemps(const std::string& target) {
  namespace fs = std::filesystem;
  std::vector<std::string> removed;
  const fs::path t(target);
  const std::string prefix = t.filename().string() + ".tmp.";
  std::error_code ec;
  fs::directory_iterator it(t.parent_path().empty() ? fs::path(".") : t.parent_path(), ec);
  if (ec) return removed;
  std::vector<fs::path> candidates;
  for (const fs::directory_entry& e : it) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    // "<prefix><pid>" or "<prefix><pid>.old"
    std::string rest = name.substr(prefix.size());
    if (rest.size() > 4 && rest.compare(rest.size() - 4, 4, ".old") == 0) rest.resize(rest.size() - 4);
    if (rest.empty() || rest.find_first_not_of("0123456789") != std::string::npos || rest.size() > 9) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(rest));
    if (pid == ::getpid()) continue;
    if (::kill(pid, 0) == 0 || errno != ESRCH) continue;  // alive (or not ours to judge)
    candidates.push_back(e.path());
  }
  std::sort(candidates.begin(), candidates.end());
  for (const fs::path& p : candidates) {
    fs::remove_all(p, ec);
    if (!ec) removed.push_back(p.string());
  }
  return removed;
}

OutputLock::OutputLock(const std::string& target, const std::string& option) : path_(target + ".lock") {
  fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw InputError(option, "cannot create lock file " + path_ + ": " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    throw InputError(option, target + " is being written by another dynref process (lock " + path_ + " is held)");
  }
}

OutputLock::~OutputLock() {
  if (fd_ < 0) return;
  ::unlink(path_.c_str());  // while still held: a waiting process fails fast, a later one makes a new file
  ::flock(fd_, LOCK_UN);
  ::close(fd_);
}

}  // namespace dynref
