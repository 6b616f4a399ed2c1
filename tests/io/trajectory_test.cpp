// TUM trajectory reader validation and the atomic writer.
#include <catch2/catch.hpp>

#include <fstream>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.h"
#include "io/trajectory.h"
#include "test_support.h"

using namespace dynref;

namespace {

std::string WriteFileIn(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

// Expects an InputError whose message names path and the given line ("path:line:").
void ExpectError(const std::string& path, int line, const std::string& fragment,
                 const TumReadOptions& options = {}) {
  try {
    ReadTumTrajectory(path, options);
    FAIL("no error for " << path);
  } catch (const InputError& e) {
    const std::string what = e.what();
    INFO(what);
    CHECK(e.file() == path);
    CHECK(e.line() == line);
    if (line > 0) CHECK(what.find(path + ":" + std::to_string(line) + ":") == 0);
    CHECK(what.find(fragment) != std::string::npos);
  }
}

const char* kGood =
    "# timestamp tx ty tz qx qy qz qw\n"
    "1.0 0 0 0 0 0 0 1\n"
    "1.1,0.1,0,0,0,0,0,1\n"  // commas are accepted, as associate.py
    "1.2\t0.2 0 0 0 0 0.0 1.0\n";

}  // namespace

TEST_CASE("trajectory: reads comments, separators, normalises near-unit quaternions") {
  const std::string dir = test::ScratchDir("io_traj_read");
  const TumTrajectory t = ReadTumTrajectory(WriteFileIn(dir, "good.txt", kGood));
  REQUIRE(t.poses.size() == 3);
  CHECK(t.lines == std::vector<int>{2, 3, 4});
  CHECK(t.poses[1].stamp == 1.1);
  CHECK(t.poses[2].T_wc.translation().x() == 0.2);
  const TumTrajectory n = ReadTumTrajectory(
      WriteFileIn(dir, "near.txt", "1 0 0 0 0 0 0 1.0009\n2 0 0 0 0.7071 0 0 0.7071\n"));
  CHECK(n.quaternions_normalised == 2);
  CHECK(n.poses[0].T_wc.linear().isApprox(Eigen::Matrix3d::Identity(), 1e-15));
  CHECK(std::abs(Eigen::Quaterniond(n.poses[1].T_wc.linear()).norm() - 1.0) < 1e-12);
}

TEST_CASE("trajectory: every bad input names file and line") {
  const std::string dir = test::ScratchDir("io_traj_bad");
  ExpectError(dir + "/missing.txt", 0, "file not found");
  ExpectError(WriteFileIn(dir, "fields.txt", "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n"), 2,
              "malformed line");
  ExpectError(WriteFileIn(dir, "nonnum.txt", "# c\n1 0 0 0 0 0 0 1\n2 0 zero 0 0 0 0 1\n"), 3,
              "field ty 'zero' is not a number");
  ExpectError(WriteFileIn(dir, "stamp.txt", "1x 0 0 0 0 0 0 1\n"), 1, "timestamp '1x'");
  ExpectError(WriteFileIn(dir, "nan.txt", "1 0 0 0 0 0 0 1\n2 nan 0 0 0 0 0 1\n"), 2,
              "NaN/inf pose");
  ExpectError(WriteFileIn(dir, "inf.txt", "1 0 0 0 0 0 0 1\n2 0 0 -inf 0 0 0 1\n"), 2,
              "NaN/inf pose");
  // issue 20 item 9: tx = 1e300 gave "rmse inf ... std -nan" with exit 0 in dynref eval.
  ExpectError(WriteFileIn(dir, "huge.txt", "1 0 0 0 0 0 0 1\n2 1e300 0 0 0 0 0 1\n"), 2, "beyond 1e9 m");
  ExpectError(WriteFileIn(dir, "quat.txt", "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1.01\n"), 2,
              "quaternion not normalised");
  ExpectError(WriteFileIn(dir, "zeroq.txt", "1 0 0 0 0 0 0 0\n"), 1, "quaternion not normalised");
  ExpectError(WriteFileIn(dir, "order.txt", "1 0 0 0 0 0 0 1\n3 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n"),
              3, "timestamps not increasing");
  ExpectError(WriteFileIn(dir, "empty.txt", "# only a comment\n\n"), 0, "no poses");
  TumReadOptions strict;
  strict.duplicates = DuplicateStamps::kError;
  ExpectError(WriteFileIn(dir, "dup.txt", "1 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n"), 2,
              "duplicate timestamp", strict);
}

TEST_CASE("trajectory: duplicate stamps kept last (TUM) or all (evo)") {
  const std::string dir = test::ScratchDir("io_traj_dup");
  const std::string path =
      WriteFileIn(dir, "dup.txt", "1 0 0 0 0 0 0 1\n1 5 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n");
  const TumTrajectory last = ReadTumTrajectory(path);
  REQUIRE(last.poses.size() == 2);
  CHECK(last.poses[0].T_wc.translation().x() == 5.0);
  CHECK(last.lines[0] == 2);
  CHECK(last.duplicates_dropped == 1);
  TumReadOptions all;
  all.duplicates = DuplicateStamps::kKeepAll;
  const TumTrajectory kept = ReadTumTrajectory(path, all);
  CHECK(kept.poses.size() == 3);
  CHECK(kept.duplicate_stamps == 1);
}

TEST_CASE("trajectory: writer round-trips exactly and leaves no temp file") {
  const std::string dir = test::ScratchDir("io_traj_write");
  std::vector<StampedPose> poses(3);
  for (int i = 0; i < 3; ++i) {
    poses[i].stamp = 1305031453.359684 + 0.1 * i;
    poses[i].T_wc = MakeSE3(Eigen::Vector3d(0.1 * i, -1.0 / 3.0, 2.0 + i),
                            Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * i + 0.1,
                                                                 Eigen::Vector3d(1, 2, 3).normalized())));
  }
  const std::string path = dir + "/traj.txt";
  TumWriteOptions opt;
  opt.header = "dynref test\nsecond line";
  WriteTumTrajectory(path, poses, opt);
  struct stat st;
  CHECK(::stat((path + ".tmp." + std::to_string(::getpid())).c_str(), &st) != 0);
  const TumTrajectory back = ReadTumTrajectory(path);
  REQUIRE(back.poses.size() == 3);
  for (int i = 0; i < 3; ++i) {
    CHECK(back.poses[i].stamp == poses[i].stamp);
    CHECK(back.poses[i].T_wc.translation() == poses[i].T_wc.translation());
    CHECK(back.poses[i].T_wc.linear().isApprox(poses[i].T_wc.linear(), 1e-15));
  }
  CHECK(back.lines[0] == 3);  // two header lines

  TumWriteOptions fixed;
  fixed.format = TumWriteOptions::Format::kFixed;
  StampedPose p;
  p.stamp = 1305031453.359684;
  p.T_wc.translation() = Eigen::Vector3d(1.5, -0.25, 0);
  CHECK(FormatTumPoseLine(p, fixed) ==
        "1305031453.359684 1.500000000 -0.250000000 0.000000000 0.000000000 0.000000000 "
        "0.000000000 1.000000000");
  // qw >= 0 is the canonical sign.
  p.T_wc.linear() = Eigen::Quaterniond(-0.5, 0.5, 0.5, 0.5).toRotationMatrix();
  CHECK(FormatTumPoseLine(p, fixed).substr(FormatTumPoseLine(p, fixed).size() - 11) ==
        "0.500000000");
}

TEST_CASE("text inputs: a UTF-8 byte-order mark is named (issue 20 item 10)") {
  const std::string dir = test::ScratchDir("io_bom");
  ExpectError(WriteFileIn(dir, "bom.txt", "\xEF\xBB\xBF" "1 0 0 0 0 0 0 1\n"), 1, "UTF-8 byte-order mark");
}
