// dynref_fuzz: deterministic mutation fuzzing of dynref's input readers (issue 20).
//   dynref_fuzz TARGET|all [--execs N] [--seed S] [--work DIR] [--list]
// Not coverage guided: every execution mutates one seed (tests/fuzz/mutator.h) and runs the
// target's readers. Outcomes: accepted, rejected with InputError (the contract: a clear message
// naming the file), an "unclear" rejection (any other exception: a finding), a crash (a finding:
// the process dies by its signal after naming target, execution and the input file), or an
// execution slower than 1 s (a finding). Exit 0 when no target had a finding, 1 otherwise.
#include <csignal>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/core.hpp>
#include <unistd.h>

#include "core/error.h"
#include "fuzz_targets.h"
#include "mutator.h"

namespace fs = std::filesystem;
using namespace dynref;

namespace {

char g_crash_note[1024] = "";

void OnCrash(int sig) {
  const ssize_t n = ::write(2, g_crash_note, std::strlen(g_crash_note));
  (void)n;
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void Spit(const std::string& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

struct Summary {
  long execs = 0, accepted = 0, rejected = 0, unclear = 0, slow = 0;
  double max_ms = 0, total_s = 0;
  std::map<std::string, long> unclear_messages;  // first line of the message -> count
};

Summary Fuzz(const fuzz::Target& target, long execs, uint64_t seed, const std::string& work) {
  fs::remove_all(work);
  fs::create_directories(work);
  const std::vector<fuzz::Seed> seeds = target.setup(work);
  std::map<std::string, std::string> valid;  // file -> its first (valid) seed
  for (const fuzz::Seed& s : seeds) valid.emplace(s.file, s.bytes);
  for (const auto& [file, bytes] : valid) Spit(work + "/" + file, bytes);
  target.run(work);  // the valid folder must read (else the target is broken, not the reader)

  Rng rng(seed, "fuzz." + target.name);
  Summary s;
  const auto start = std::chrono::steady_clock::now();
  for (long i = 0; i < execs; ++i) {
    const fuzz::Seed& base = seeds[static_cast<size_t>(rng.UniformInt(0, static_cast<int64_t>(seeds.size()) - 1))];
    const std::string path = work + "/" + base.file;
    Spit(path, fuzz::Mutate(base.bytes, rng));
    std::snprintf(g_crash_note, sizeof g_crash_note,
                  "\ndynref_fuzz: CRASH in target %s, execution %ld (seed %llu); input: %s\n",
                  target.name.c_str(), i, static_cast<unsigned long long>(seed), path.c_str());
    const auto t0 = std::chrono::steady_clock::now();
    try {
      target.run(work);
      ++s.accepted;
    } catch (const InputError&) {
      ++s.rejected;
    } catch (const std::exception& e) {
      ++s.unclear;
      std::string msg = e.what();
      msg = msg.substr(0, msg.find('\n')).substr(0, 160);
      if (s.unclear_messages.size() < 20 || s.unclear_messages.count(msg)) ++s.unclear_messages[msg];
      fs::copy_file(path, work + "/unclear_" + std::to_string(s.unclear) + "_" +
                              fs::path(base.file).filename().string(),
                    fs::copy_options::overwrite_existing);
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    s.max_ms = std::max(s.max_ms, ms);
    if (ms > 1000) ++s.slow;
    ++s.execs;
    Spit(path, valid.at(base.file));
    if (isatty(2) && (i + 1) % 10000 == 0)
      std::fprintf(stderr, "\r%s: %ld/%ld", target.name.c_str(), i + 1, execs);
  }
  s.total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (isatty(2)) std::fprintf(stderr, "\r");
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  cv::setNumThreads(0);
  cv::setBreakOnError(false);
  std::string which = argc > 1 ? argv[1] : "";
  long execs = 10000;
  uint64_t seed = 1;
  bool own_work = true;  // the default folder is removed after a run without findings
  // Two small file writes per execution: on tmpfs that is ~10x faster than on a disk.
  std::string work = (fs::is_directory("/dev/shm") ? std::string("/dev/shm")
                                                   : fs::temp_directory_path().string()) +
                     "/dynref_fuzz." + std::to_string(::getpid());
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--execs" && i + 1 < argc) execs = std::stol(argv[++i]);
    else if (a == "--seed" && i + 1 < argc) seed = std::stoull(argv[++i]);
    else if (a == "--work" && i + 1 < argc) work = argv[++i], own_work = false;
    else {
      std::fprintf(stderr, "dynref_fuzz: unknown argument %s\n", a.c_str());
      return 2;
    }
  }
  const std::vector<fuzz::Target> targets = fuzz::AllTargets();
  if (which.empty() || which == "--list") {
    for (const auto& t : targets) std::printf("%-14s %s\n", t.name.c_str(), t.what.c_str());
    return which.empty() ? 2 : 0;
  }
  for (int sig : {SIGSEGV, SIGABRT, SIGBUS, SIGFPE, SIGILL}) std::signal(sig, OnCrash);
  bool findings = false, ran = false;
  std::printf("| target | executions | accepted | rejected (InputError) | unclear | slow (>1 s) | max ms | exec/s |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const auto& t : targets) {
    if (which != "all" && which != t.name) continue;
    ran = true;
    const Summary s = Fuzz(t, execs, seed, work + "/" + t.name);
    std::printf("| %s | %ld | %ld | %ld | %ld | %ld | %.1f | %.0f |\n", t.name.c_str(), s.execs,
                s.accepted, s.rejected, s.unclear, s.slow, s.max_ms, s.execs / std::max(s.total_s, 1e-9));
    std::fflush(stdout);
    for (const auto& [msg, n] : s.unclear_messages)
      std::fprintf(stderr, "  %s unclear x%ld: %s\n", t.name.c_str(), n, msg.c_str());
    findings = findings || s.unclear > 0 || s.slow > 0;
  }
  if (!ran) {
    std::fprintf(stderr, "dynref_fuzz: unknown target '%s' (--list shows them)\n", which.c_str());
    return 2;
  }
  if (findings) std::fprintf(stderr, "dynref_fuzz: inputs of the findings are in %s\n", work.c_str());
  else if (own_work) fs::remove_all(work);
  return findings ? 1 : 0;
}
