// workflow/Snakefile and `dynref reproduce` write byte-identical reports for the same matrix
// (issue 19: 2 sequences x 2 methods x 2 seeds, plus the eta/lambda sweep through `run --set`),
// `--collect` refuses folders made with other arguments, and the Slurm profile's dry run passes.
#include <catch2/catch.hpp>
#include <sstream>
#include <string>

#include "test_support.h"

using namespace dynref;

namespace {

std::string Snakemake() {
  const std::string exe = DYNREF_SNAKEMAKE_EXE;
  // Not a skip: the workflow is a deliverable, and scripts/install-deps.sh installs snakemake.
  if (exe.empty() || exe.find("NOTFOUND") != std::string::npos)
    FAIL("snakemake not found at configure time (apt-get install snakemake, or bash scripts/install-deps.sh)");
  return exe;
}

const char* const kMatrix = " --frames 45 --seeds 1,2 --sequences walking_xyz,sitting_static --variants orb,sgdo_nodense";

std::string SnakeConfig(const std::string& work, const std::string& reports) {
  return " --config dynref=" + test::DynrefExe() + " work=" + work + " reports=" + reports +
         " headline_frames=45 ablation_frames=45 'headline_seeds=[1,2]' 'ablation_seeds=[1,2]'"
         " 'sequences=[walking_xyz,sitting_static]' 'variants=[orb,sgdo_nodense]'"
         " 'sensitivity=[walking_xyz]' 'tables=[sgdo-table6,sgdo-table1,mgd-table2]'"
         " 'table_args={mgd-table2: --no-ablations --sequences walking_xyz}' sgdo_jobs=per-call";
}

}  // namespace

TEST_CASE("workflow: snakemake -j 2 and dynref reproduce write byte-identical reports", "[cli][slow]") {
  const std::string snake = Snakemake();
  const std::string dir = test::ScratchDir("workflow_matrix");
  const test::CommandResult a = test::RunDynref(std::string("reproduce sgdo-table6") + kMatrix + " --sensitivity walking_xyz --work " +
                                                dir + "/a --out " + dir + "/ra/sgdo-table6.md");
  INFO(a.output);
  REQUIRE(a.exit_code == 0);
  const test::CommandResult a1 = test::RunDynref(std::string("reproduce sgdo-table1 --frames 45 --seeds 1,2 --sequences "
                                                             "walking_xyz,sitting_static --reuse --work ") +
                                                 dir + "/a --out " + dir + "/ra/sgdo-table1.md");
  INFO(a1.output);
  REQUIRE(a1.exit_code == 0);
  CHECK(a1.output.find("reproduce: run") == std::string::npos);  // every run reused from table 6
  // A table outside the SGDO matrix: the workflow runs it seed by seed, then --collect.
  const test::CommandResult a2 = test::RunDynref("reproduce mgd-table2 --frames 45 --seeds 1,2 --no-ablations --sequences "
                                                 "walking_xyz --work " + dir + "/a2 --out " + dir + "/ra/mgd-table2.md");
  INFO(a2.output);
  REQUIRE(a2.exit_code == 0);
  const test::CommandResult b = test::RunShell("cd " + test::Quote(test::SourcePath("")) + " && " + snake +
                                               " -s workflow/Snakefile -d " + dir + "/snake -j 2 --quiet" +
                                               SnakeConfig(dir + "/b", dir + "/rb") + " 2>&1");
  INFO(b.output);
  REQUIRE(b.exit_code == 0);
  for (const char* report : {"sgdo-table6.md", "sgdo-table6_overlay.png", "sgdo-table6_ablation_walking_xyz.png",
                             "sgdo-table6_trajectories.png", "sgdo-table6_ate_time.png", "sgdo-table1.md", "sgdo-table1.png",
                             "mgd-table2.md", "mgd-table2.png"}) {
    INFO(report);
    const std::string ra = test::ReadFileBytes(dir + "/ra/" + report);
    CHECK(!ra.empty());
    CHECK(ra == test::ReadFileBytes(dir + "/rb/" + report));
  }
  // The workflow's eval jobs wrote their JSON next to the runs.
  CHECK(test::FileExists(dir + "/b/sgdo-main/seed2/eval/sitting_static/sgdo_nodense.json"));
  CHECK(test::FileExists(dir + "/b/sgdo-table6/seed1/runs/walking_xyz/sens_eta0.05_lambda100/run.json"));
  CHECK(test::FileExists(dir + "/b/mgd-table2/seed2/runs/walking_xyz/mgd/run.json"));

  SECTION("--collect refuses a run made with another config, and a missing run, naming the folder") {
    // Swap two runs: the orb folder now holds an sgdo run.
    REQUIRE(test::RunShell("cd " + dir + "/b/sgdo-table6/seed1/runs/walking_xyz && mv orb orb.keep && cp -r sgdo_nodense orb").exit_code == 0);
    test::ExpectBadInput(std::string("reproduce sgdo-table6 --collect") + kMatrix + " --sensitivity none --work " + dir +
                             "/b/sgdo-table6 --out " + dir + "/rc/t.md",
                         "seed1/runs/walking_xyz/orb/run.json: ran a different config");
    REQUIRE(test::RunShell("rm -rf " + dir + "/b/sgdo-table6/seed1/runs/walking_xyz/orb").exit_code == 0);
    test::ExpectBadInput(std::string("reproduce sgdo-table6 --collect") + kMatrix + " --sensitivity none --work " + dir +
                             "/b/sgdo-table6 --out " + dir + "/rc/t.md",
                         "seed1/runs/walking_xyz/orb: missing");
    CHECK(!test::FileExists(dir + "/rc/t.md"));
    test::ExpectBadInput(std::string("reproduce sgdo-table6 --collect --frames 46 --seeds 1 --variants orb") +
                             " --sensitivity none --sequences sitting_static --work " + dir + "/b/sgdo-table6 --out " + dir + "/rc/t.md",
                         "frames is '45', this table needs '46'");
  }
}

TEST_CASE("workflow: the Slurm profile's dry run writes every table of reproduce --list", "[cli]") {
  const std::string snake = Snakemake();
  const std::string dir = test::ScratchDir("workflow_slurm");
  const test::CommandResult r = test::RunShell("cd " + test::Quote(test::SourcePath("")) + " && " + snake +
                                               " -s workflow/Snakefile -d " + dir + " --profile workflow/profiles/slurm" +
                                               " -n --nolock --config work=" + dir + "/w reports=" + dir + "/r 2>&1");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  const test::CommandResult list = test::RunDynref("reproduce --list");
  REQUIRE(list.exit_code == 0);
  std::istringstream rows(list.output);
  std::string row;
  std::getline(rows, row);  // header
  int tables = 0;
  while (std::getline(rows, row)) {
    const std::string table = row.substr(0, row.find('\t'));
    INFO(table);
    CHECK(r.output.find(dir + "/r/" + table + ".md") != std::string::npos);
    ++tables;
  }
  CHECK(tables >= 14);
  // Headline tables at the papers' lengths (--frames 0) over seeds 1-5, ablations at 300 frames over 1-3.
  CHECK(r.output.find("reproduce mgd-table2 --frames 0 --seeds 1,2,3,4,5 --collect") != std::string::npos);
  CHECK(r.output.find("reproduce mgd-table4 --frames 300 --seeds 1,2,3 --collect") != std::string::npos);
  // SGDO tables 1, 2, 3, 4, 7 read one work folder, filled seed by seed by Table 1's jobs.
  CHECK(r.output.find("reproduce sgdo-table3 --frames 0 --seeds 1,2,3,4,5 --collect --work " + dir + "/w/sgdo-main") !=
        std::string::npos);
  CHECK(r.output.find("reproduce sgdo-table1 --frames 0 --seeds 3 --reuse --work " + dir + "/w/sgdo-main") != std::string::npos);
  CHECK(r.output.find("reproduce sgdo-table6 --frames 300 --seeds 3 --reuse --work " + dir + "/w/sgdo-table6") !=
        std::string::npos);
  // A headline table's seed job prunes its sequences' images once its runs are counted.
  CHECK(r.output.find("mgd-table2/seed1.md > " + dir + "/w/logs/table/mgd-table2_seed1.log 2>&1; for y in") != std::string::npos);
}

TEST_CASE("workflow: a regeneration checkpointed and restored in an empty work folder writes the same reports, runs reused",
          "[cli][slow]") {
  // scripts/regen-checkpoint.py (issue 38: the regeneration outlasts a machine session, whose end
  // takes its disk), with the reports in WORK/reports as scripts/regenerate-reports.sh writes them.
  // The session ends when mgd-table4's report is written and mgd-table2's seed 2 job is not done;
  // mgd-table2 prunes its sequences' images after each seed job. tests/docs/regen_checkpoint_test.py
  // covers restore's other cases (a table that keeps its images, not yet reported).
  const std::string snake = Snakemake();
  const std::string dir = test::ScratchDir("workflow_checkpoint");
  const std::string src = test::Quote(test::SourcePath(""));
  const std::string checkpoint = "python3 " + src + "/scripts/regen-checkpoint.py ";
  const std::string work = dir + "/work";
  const auto snakemake = [&]() {
    return test::RunShell("cd " + src + " && " + snake + " -s workflow/Snakefile -d " + dir + "/snake -j 2 --quiet" +
                          " --rerun-incomplete --config dynref=" + test::DynrefExe() + " work=" + work + " reports=" + work +
                          "/reports headline_frames=45 ablation_frames=45 'headline_seeds=[1,2]' 'ablation_seeds=[1]'"
                          " 'tables=[mgd-table2,mgd-table4]'"
                          " 'table_args={mgd-table2: --no-ablations --sequences walking_xyz, mgd-table4: --sequences walking_xyz}'"
                          " 2>&1");
  };
  const test::CommandResult a = snakemake();
  INFO(a.output);
  REQUIRE(a.exit_code == 0);
  const std::string report2 = test::ReadFileBytes(work + "/reports/mgd-table2.md");
  REQUIRE(test::RunShell("rm " + work + "/mgd-table2/seed2.done " + work + "/reports/mgd-table2.md").exit_code == 0);
  const test::CommandResult saved = test::RunShell(checkpoint + "save --work " + work + " --state " + dir + "/state 2>&1");
  INFO(saved.output);
  REQUIRE(saved.exit_code == 0);
  // No images (no per-frame file of a sequence); the runs' results and the written report.
  const test::CommandResult listing = test::RunShell("tar -tJf " + dir + "/state/part-001.tar.xz");
  CHECK(listing.output.find("/rgb/") == std::string::npos);
  CHECK(listing.output.find("/depth/") == std::string::npos);
  std::istringstream lines(listing.output);
  for (std::string line; std::getline(lines, line);) {
    INFO(line);
    CHECK_FALSE((line.find("/seq/") != std::string::npos && line.find(".png") != std::string::npos));
  }
  CHECK(listing.output.find("mgd-table2/seed1/seq/walking_xyz/synth.yaml") != std::string::npos);
  CHECK(listing.output.find("mgd-table2/seed1/runs/walking_xyz/mgd/trajectory.txt") != std::string::npos);
  CHECK(listing.output.find("reports/mgd-table4.md") != std::string::npos);

  // The next session: the same path (a run records its sequence's absolute path), empty.
  REQUIRE(test::RunShell("mv " + work + " " + dir + "/work.before").exit_code == 0);
  const test::CommandResult restored = test::RunShell(checkpoint + "restore --work " + work + " --state " + dir + "/state 2>&1");
  INFO(restored.output);
  REQUIRE(restored.exit_code == 0);
  CHECK(test::FileExists(work + "/mgd-table2/seed1.done"));  // pruned table, finished: its report reads no image
  CHECK(test::FileExists(work + "/mgd-table4/seed1.done"));  // its report is written: nothing of it runs again
  const test::CommandResult b = snakemake();
  INFO(b.output);
  REQUIRE(b.exit_code == 0);
  CHECK(test::ReadFileBytes(work + "/reports/mgd-table2.md") == report2);
  // Only mgd-table2's seed 2 ran again: it synthesised its sequence and reused every run.
  const std::string log = test::ReadFileBytes(work + "/logs/table/mgd-table2_seed2.log");
  CHECK(log.find("reproduce: synth") != std::string::npos);
  CHECK(log.find("reproduce: run") == std::string::npos);
  CHECK(!test::FileExists(work + "/logs/table/mgd-table2_seed1.log"));
  CHECK(!test::FileExists(work + "/logs/table/mgd-table4_seed1.log"));

  SECTION("save after a restore packs only what is new, and restore refuses a folder that is not empty") {
    REQUIRE(test::RunShell(checkpoint + "save --work " + work + " --state " + dir + "/state 2>&1").exit_code == 0);
    const test::CommandResult second = test::RunShell("tar -tJf " + dir + "/state/part-002.tar.xz");
    CHECK(second.output.find("mgd-table2/seed2.done") != std::string::npos);
    CHECK(second.output.find("reports/mgd-table2.md") != std::string::npos);
    CHECK(second.output.find("mgd-table2/seed1/runs/walking_xyz/mgd/trajectory.txt") == std::string::npos);
    const test::CommandResult again = test::RunShell(checkpoint + "restore --work " + work + " --state " + dir + "/state 2>&1");
    CHECK(again.exit_code == 2);
    CHECK(again.output.find("is not empty") != std::string::npos);
  }
}
