// `dynref trace verify` end to end (issue 32): a fresh 30-frame --trace full run of every config
// in configs/ verifies with 0 mismatched and 0 unverifiable records; a planted wrong record (one
// `after` changed, one input removed) makes it exit 1 naming the record.
#include <catch2/catch.hpp>
#include <sys/stat.h>
#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "test_support.h"
#include "trace/trace_copy.h"
#include "trace/trace_reader.h"
#include "trace/trace_writer.h"
#include "verify/verify_run.h"

namespace fs = std::filesystem;
using dynref::test::Quote;
using dynref::test::RunDynref;

namespace {

// Every config file the suite checks (a new config must join this list: the last test says so).
const std::vector<std::string> kConfigs = {
    "blur", "blur_nocomp", "blur_nodepth", "blur_noprob", "epi", "epi_A", "epi_ALL", "epi_B", "epi_BC", "epi_C",
    "mgd", "mgd_LS", "mgd_mf", "mgd_nd", "mgd_nodiff", "mgd_pro", "orb", "semantic", "semantic_nointeraction",
    "semantic_orbmap", "sgdo", "sgdo_G", "sgdo_O", "sgdo_S", "sgdo_SG", "sgdo_SGD", "sgdo_SGO", "sgdo_nodense",
    "sgdo_vote"};

// walking_xyz (seed 1, yolo-like detections) synthesised once per dynref build and shared by every
// config's test: the tests run as parallel processes, so the first one writes it under a lock and
// the others reuse it (synth publishes the folder whole, by rename). The folder is named by the
// executable's modification time and size, so a rebuilt synth never reuses an older sequence.
std::string SharedSequence(int frames) {
  struct stat st {};
  REQUIRE(::stat(dynref::test::DynrefExe().c_str(), &st) == 0);
  const std::string dir = std::string(DYNREF_BINARY_DIR) + "/test_scratch/verify_shared";
  const std::string seq = dir + "/walking_xyz_" + std::to_string(frames) + "_" + std::to_string(st.st_mtime) + "_" +
                          std::to_string(st.st_size);
  const std::string make = "test -d " + Quote(seq) + " || " + Quote(dynref::test::DynrefExe()) +
                           " synth --preset walking_xyz --seed 1 --frames " + std::to_string(frames) +
                           " --detections yolo-like --out " + Quote(seq);
  const auto s = dynref::test::RunShell("mkdir -p " + Quote(dir) + " && flock " + Quote(dir + "/.lock") + " sh -c \"" +
                                        make + "\"");
  INFO(s.output);
  REQUIRE(s.exit_code == 0);
  return seq;
}

// Runs `config` on the shared sequence at trace level full; returns the run folder.
std::string RunConfig(const std::string& config, int frames = 30) {
  const std::string dir = dynref::test::ScratchDir("verify_" + config);
  const std::string seq = SharedSequence(frames), run = dir + "/run";
  const auto r = RunDynref("run --config " + Quote(dynref::test::SourcePath("configs/" + config + ".yaml")) +
                           " --sequence " + Quote(seq) + " --detections " + Quote(seq + "/detections/yolo-like") +
                           " --trace full --out " + Quote(run));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  return run;
}

void CheckConfigVerifies(const std::string& config) {
  const std::string run = RunConfig(config);
  const auto v = RunDynref("trace verify " + Quote(run));
  INFO(v.output);
  CHECK(v.exit_code == 0);
  CHECK(v.output.find("verified: every record recomputed from the trace") != std::string::npos);
}

}  // namespace

// The method configs run in every CI; their ablation variants (the same stages with some switched
// off) carry [slow] and run with `scripts/test.sh --all` (CI budget).
#define DYNREF_VERIFY_CONFIG_TEST(name, tags) \
  TEST_CASE("trace verify end to end: configs/" #name ".yaml, 30 frames, every record recomputed", "[verify][cli]" tags) { \
    CheckConfigVerifies(#name);                                                                     \
  }
DYNREF_VERIFY_CONFIG_TEST(blur, "")
DYNREF_VERIFY_CONFIG_TEST(blur_nocomp, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(blur_nodepth, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(blur_noprob, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(epi, "")
DYNREF_VERIFY_CONFIG_TEST(epi_A, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(epi_ALL, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(epi_B, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(epi_BC, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(epi_C, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(mgd, "")
DYNREF_VERIFY_CONFIG_TEST(mgd_LS, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(mgd_mf, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(mgd_nd, "")
DYNREF_VERIFY_CONFIG_TEST(mgd_nodiff, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(mgd_pro, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(orb, "")
DYNREF_VERIFY_CONFIG_TEST(semantic, "")
DYNREF_VERIFY_CONFIG_TEST(semantic_nointeraction, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(semantic_orbmap, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(sgdo, "")
DYNREF_VERIFY_CONFIG_TEST(sgdo_G, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(sgdo_O, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(sgdo_S, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(sgdo_SG, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(sgdo_SGD, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(sgdo_SGO, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(sgdo_nodense, "[slow]")
DYNREF_VERIFY_CONFIG_TEST(sgdo_vote, "[slow]")

TEST_CASE("trace verify: every config in configs/ has its end-to-end test", "[verify]") {
  std::set<std::string> on_disk;
  for (const auto& e : fs::directory_iterator(dynref::test::SourcePath("configs")))
    if (e.path().extension() == ".yaml") on_disk.insert(e.path().stem().string());
  CHECK(on_disk == std::set<std::string>(kConfigs.begin(), kConfigs.end()));
}

namespace {

// Copies `in` to `out` through the writer, letting `edit` change (or drop: return false) records.
template <class Edit>
void Rewrite(const std::string& in, const std::string& out, Edit edit) {
  using namespace dynref::trace;
  TraceReader reader(in);
  TraceWriter w(out, reader.level(), HeaderOf(reader));
  for (size_t g = 0; g < reader.groups().size(); ++g)
    for (Record r : reader.ReadGroup(g))
      if (edit(r)) WriteRecord(w, r);
  w.Close(reader.end_state());
}

}  // namespace

TEST_CASE("trace verify end to end: a planted wrong record is a mismatch, a removed input unverifiable", "[verify][cli]") {
  const std::string run = RunConfig("mgd", 8);
  const std::string dir = fs::path(run).parent_path().string();
  const std::string trace = run + "/trace.dtr";
  // The first mgd.smooth record of frame >= 2: change its `after`, then (another copy) drop its input `a`.
  std::string target;
  {
    dynref::trace::TraceReader reader(trace);
    for (size_t g = 0; g < reader.groups().size() && target.empty(); ++g)
      for (const auto& r : reader.ReadGroup(g))
        if (r.frame >= 2 && r.type == dynref::trace::RecordType::kProbability && r.stage == "mgd.smooth") {
          target = r.entity;
          break;
        }
  }
  REQUIRE(!target.empty());
  const std::string changed = dir + "/changed.dtr", dropped = dir + "/dropped.dtr";
  Rewrite(trace, changed, [&](dynref::trace::Record& r) {
    if (r.type == dynref::trace::RecordType::kProbability && r.stage == "mgd.smooth" && r.entity == target)
      r.after = r.after + 0.01;
    return true;
  });
  Rewrite(trace, dropped, [&](dynref::trace::Record& r) {
    if (r.type == dynref::trace::RecordType::kProbability && r.stage == "mgd.smooth" && r.entity == target)
      r.inputs.erase(std::remove_if(r.inputs.begin(), r.inputs.end(), [](const auto& v) { return v.name == "a"; }),
                     r.inputs.end());
    return true;
  });
  const auto original = RunDynref("trace verify " + Quote(trace));
  INFO(original.output);
  CHECK(original.exit_code == 0);
  const auto c = RunDynref("trace verify " + Quote(changed) + " --stage mgd.smooth");
  INFO(c.output);
  CHECK(c.exit_code == 1);
  CHECK(c.output.find("mismatch frame") != std::string::npos);
  CHECK(c.output.find("mgd.smooth " + target + " field after") != std::string::npos);
  const auto d = RunDynref("trace verify " + Quote(dropped) + " --stage mgd.smooth");
  INFO(d.output);
  CHECK(d.exit_code == 1);
  CHECK(d.output.find("unverifiable frame") != std::string::npos);
  CHECK(d.output.find("mgd.smooth " + target) != std::string::npos);
}

TEST_CASE("trace verify: a trace below level full and a missing file are bad input", "[verify][cli]") {
  const std::string dir = dynref::test::ScratchDir("verify_bad_input");
  const auto s = RunDynref("synth --preset static_xyz --seed 1 --frames 3 --out " + Quote(dir + "/seq"));
  REQUIRE(s.exit_code == 0);
  const auto r = RunDynref("run --method orb --sequence " + Quote(dir + "/seq") + " --trace frames --out " + Quote(dir + "/run"));
  REQUIRE(r.exit_code == 0);
  dynref::test::ExpectBadInput("trace verify " + Quote(dir + "/run"), "only a --trace full run");
  dynref::test::ExpectBadInput("trace verify " + Quote(dir + "/nothing"), "nothing");
  dynref::test::ExpectBadInput("trace verify " + Quote(dir + "/run") + " --frames 5-2", "--frames");
}
