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
