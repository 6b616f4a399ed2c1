// A run folder is published as a unit (issue 20, items 2-5 and 11): written in a staging folder,
// locked against a second writer, renamed onto --out only when every output is closed; a
// failed component write or trace write ends the run in error; a rerun never keeps files of the
// earlier run; a killed run leaves the earlier folder intact and its staging folder is removed
// by the next run.
#include <catch2/catch.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "core/atomic_file.h"
#include "synth/synth.h"
#include "test_support.h"

using namespace dynref;
namespace fs = std::filesystem;

namespace {

std::string Sequence(const std::string& dir, int frames = 12) {
  synth::SynthOptions so;
  so.preset = "walking_xyz";
  so.frames = frames;
  so.seed = 5;
  so.detections = "yolo-like";
  so.out = dir + "/seq";
  synth::GenerateSequence(so);
  return so.out;
}

std::string RunArgs(const std::string& seq, const std::string& out, const std::string& method = "orb") {
  return "run --method " + method + " --sequence " + test::Quote(seq) + " --out " + test::Quote(out) +
         " --detections " + test::Quote(seq + "/detections/yolo-like");
}

nlohmann::json RunJson(const std::string& dir) {
  std::ifstream in(dir + "/run.json");
  return nlohmann::json::parse(in);
}

// Siblings of `out` whose name starts with "<name>.tmp." or is "<name>.lock".
int Leftovers(const std::string& out) {
  int n = 0;
  const std::string name = fs::path(out).filename().string();
  for (const auto& e : fs::directory_iterator(fs::path(out).parent_path())) {
    const std::string f = e.path().filename().string();
    n += f.rfind(name + ".tmp.", 0) == 0 || f == name + ".lock";
  }
  return n;
}

}  // namespace

TEST_CASE("run folder: a failed dense-map write ends the run in error and says so in run.json", "[cli]") {
  const std::string dir = test::ScratchDir("run_folder_ply");
  const std::string seq = Sequence(dir);
  std::string cfg = test::ReadFileBytes(test::SourcePath("configs/sgdo.yaml"));
  const std::string from = "output: {value: dense_map.ply,";
  REQUIRE(cfg.find(from) != std::string::npos);
  cfg.replace(cfg.find(from), from.size(), "output: {value: /nonexistent-dynref-dir/dense_map.ply,");
  const std::string cfg_path = test::WriteText(dir + "/sgdo_bad_output.yaml", cfg);
  const auto r = test::RunDynref(RunArgs(seq, dir + "/run", "sgdo") + " --config " + test::Quote(cfg_path));
  INFO(r.output);
  CHECK(r.exit_code == 2);
  const nlohmann::json j = RunJson(dir + "/run");
  CHECK(j["end_state"].get<std::string>().rfind("error: output sgdo.densemap: ", 0) == 0);
  CHECK(j["output_errors"].size() == 1);
  CHECK(Leftovers(dir + "/run") == 0);
}

TEST_CASE("run folder: a rerun replaces the whole folder (no dense map of an earlier sgdo run)", "[cli]") {
  const std::string dir = test::ScratchDir("run_folder_rerun");
  const std::string seq = Sequence(dir);
  REQUIRE(test::RunDynref(RunArgs(seq, dir + "/run", "sgdo") + " --trace full").exit_code == 0);
  REQUIRE(fs::exists(dir + "/run/dense_map.ply"));
  REQUIRE(fs::exists(dir + "/run/trace.dtr"));
  const auto r = test::RunDynref(RunArgs(seq, dir + "/run", "orb") + " --trace off");
  REQUIRE(r.exit_code == 0);
  CHECK_FALSE(fs::exists(dir + "/run/dense_map.ply"));
  CHECK_FALSE(fs::exists(dir + "/run/trace.dtr"));
  CHECK(RunJson(dir + "/run")["method"] == "orb");
  CHECK(Leftovers(dir + "/run") == 0);
}

TEST_CASE("run folder: a folder that is not a run is never replaced", "[cli]") {
  const std::string dir = test::ScratchDir("run_folder_foreign");
  const std::string seq = Sequence(dir);
  fs::create_directories(dir + "/mine");
  test::WriteText(dir + "/mine/notes.txt", "my notes\n");
  const auto r = test::RunDynref(RunArgs(seq, dir + "/mine"));
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("is not a dynref run folder") != std::string::npos);
  CHECK(test::ReadFileBytes(dir + "/mine/notes.txt") == "my notes\n");
}

TEST_CASE("run folder: a second writer of the same --out fails at once, naming the lock", "[cli]") {
  const std::string dir = test::ScratchDir("run_folder_lock");
  const std::string seq = Sequence(dir);
  const std::string out = StagingDirectory::NormalisedTarget(dir + "/run");
  {
    const OutputLock held(out, "--out");  // another process writing the folder
    const auto r = test::RunDynref(RunArgs(seq, out));
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("is being written by another dynref process") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
  }
  CHECK(test::RunDynref(RunArgs(seq, out)).exit_code == 0);  // released: runs
  CHECK(Leftovers(out) == 0);
}

TEST_CASE("run folder: a killed run leaves the earlier folder intact, the next run removes its staging", "[cli]") {
  const std::string dir = test::ScratchDir("run_folder_kill");
  const std::string seq = Sequence(dir, 60);
  const std::string out = dir + "/run";
  REQUIRE(test::RunDynref(RunArgs(seq, out) + " --frames 0-9").exit_code == 0);
  const std::string before = test::ReadFileBytes(out + "/run.json");
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    const std::string log = dir + "/killed.log";
    execl(test::DynrefExe().c_str(), "dynref", "run", "--method", "sgdo", "--sequence", seq.c_str(), "--out",
          out.c_str(), "--detections", (seq + "/detections/yolo-like").c_str(), "--trace", "full", (char*)nullptr);
    _exit(127);
  }
  // Wait until the run is writing its staging folder, then kill it.
  const std::string staging = out + ".tmp." + std::to_string(pid);
  for (int i = 0; i < 400 && !fs::exists(staging + "/trace.dtr.tmp." + std::to_string(pid)); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  REQUIRE(WIFSIGNALED(status));
  CHECK(fs::exists(staging));                                   // what the killed run left
  CHECK(test::ReadFileBytes(out + "/run.json") == before);      // the earlier run is untouched
  CHECK_FALSE(fs::exists(out + "/dense_map.ply"));
  REQUIRE(test::RunDynref(RunArgs(seq, out) + " --frames 0-9").exit_code == 0);
  CHECK_FALSE(fs::exists(staging));                             // removed by the next run
  CHECK(Leftovers(out) == 0);
}

TEST_CASE("run folder: a failed trace write (disk full) never publishes a folder that says complete", "[cli]") {
  const std::string dir = test::ScratchDir("run_folder_full");
  const std::string seq = Sequence(dir);
  const std::string mnt = dir + "/small";
  fs::create_directories(mnt);
  // A 256 KiB tmpfs in a private mount namespace: the full trace of 12 frames does not fit.
  const auto r = test::RunShell("unshare -m sh -c " +
                                test::Quote("mount -t tmpfs -o size=256k tmpfs " + mnt + " && " + test::DynrefExe() +
                                            " " + RunArgs(seq, mnt + "/run") + " --trace full; echo exit=$?; echo LISTING; ls -a " +
                                            mnt + "; cat " + mnt + "/run/run.json 2>/dev/null | grep end_state"));
  INFO(r.output);
  REQUIRE(r.output.find("exit=") != std::string::npos);  // the mount worked and the run ran
  CHECK(r.output.find("exit=0") == std::string::npos);
  CHECK(r.output.find("\"end_state\": \"complete\"") == std::string::npos);
  const size_t listing = r.output.find("LISTING");
  REQUIRE(listing != std::string::npos);
  CHECK(r.output.find("run.tmp.", listing) == std::string::npos);  // no staging folder left behind
}

TEST_CASE("run folder: an unknown trace level creates nothing", "[cli]") {
  const std::string dir = test::ScratchDir("run_folder_level");
  const auto r = test::RunDynref("run --sequence " + test::Quote(test::SourcePath("datasets/real/tum_fr1_desk_9frames")) +
                                 " --out " + test::Quote(dir + "/a/b") + " --trace verbose");
  CHECK(r.exit_code == 2);
  CHECK_FALSE(fs::exists(dir + "/a"));
}
