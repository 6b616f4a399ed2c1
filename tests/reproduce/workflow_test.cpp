// workflow/Snakefile and `dynref reproduce` write byte-identical reports for the same matrix
// (issue 19: 2 sequences x 2 methods x 2 seeds, plus the eta/lambda sweep through `run --set`),
// `--collect` refuses folders made with other arguments, and the Slurm profile's dry run passes.
#include <catch2/catch.hpp>
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
         " frames=45 'seeds=[1,2]' 'sequences=[walking_xyz,sitting_static]' 'variants=[orb,sgdo_nodense]'"
         " 'sensitivity=[walking_xyz]' 'tables=[sgdo-table6,sgdo-table1]'";
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
  const test::CommandResult b = test::RunShell("cd " + test::Quote(test::SourcePath("")) + " && " + snake +
                                               " -s workflow/Snakefile -d " + dir + "/snake -j 2 --quiet" +
                                               SnakeConfig(dir + "/b", dir + "/rb") + " 2>&1");
  INFO(b.output);
  REQUIRE(b.exit_code == 0);
  for (const char* report : {"sgdo-table6.md", "sgdo-table6_overlay.png", "sgdo-table6_ablation_walking_xyz.png",
                             "sgdo-table6_trajectories.png", "sgdo-table6_ate_time.png", "sgdo-table1.md", "sgdo-table1.png"}) {
    INFO(report);
    const std::string ra = test::ReadFileBytes(dir + "/ra/" + report);
    CHECK(!ra.empty());
    CHECK(ra == test::ReadFileBytes(dir + "/rb/" + report));
  }
  // The workflow's eval jobs wrote their JSON next to the runs.
  CHECK(test::FileExists(dir + "/b/seed2/eval/sitting_static/sgdo_nodense.json"));
  CHECK(test::FileExists(dir + "/b/seed1/runs/walking_xyz/sens_eta0.05_lambda100/run.json"));

  SECTION("--collect refuses a run made with another config, and a missing run, naming the folder") {
    // Swap two runs: the orb folder now holds an sgdo run.
    REQUIRE(test::RunShell("cd " + dir + "/b/seed1/runs/walking_xyz && mv orb orb.keep && cp -r sgdo_nodense orb").exit_code == 0);
    test::ExpectBadInput(std::string("reproduce sgdo-table6 --collect") + kMatrix + " --sensitivity none --work " + dir +
                             "/b --out " + dir + "/rc/t.md",
                         "seed1/runs/walking_xyz/orb/run.json: ran a different config");
    REQUIRE(test::RunShell("rm -rf " + dir + "/b/seed1/runs/walking_xyz/orb").exit_code == 0);
    test::ExpectBadInput(std::string("reproduce sgdo-table6 --collect") + kMatrix + " --sensitivity none --work " + dir +
                             "/b --out " + dir + "/rc/t.md",
                         "seed1/runs/walking_xyz/orb: missing");
    CHECK(!test::FileExists(dir + "/rc/t.md"));
    test::ExpectBadInput(std::string("reproduce sgdo-table6 --collect --frames 46 --seeds 1 --variants orb") +
                             " --sensitivity none --sequences sitting_static --work " + dir + "/b --out " + dir + "/rc/t.md",
                         "frames is '45', this table needs '46'");
  }
}

TEST_CASE("workflow: the Slurm profile's dry run passes") {
  const std::string snake = Snakemake();
  const std::string dir = test::ScratchDir("workflow_slurm");
  const test::CommandResult r = test::RunShell("cd " + test::Quote(test::SourcePath("")) + " && " + snake +
                                               " -s workflow/Snakefile -d " + dir + " --profile workflow/profiles/slurm" +
                                               " -n --quiet --nolock --config work=" + dir + "/w 2>&1");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("run ") != std::string::npos);
}
