// issue 20 item 1: `dynref overlay` on a full disk exited 0 with truncated and 0-byte PNGs
// (Canvas::WritePng trusted OIIO's write()). Now the PNG is encoded in memory and written through
// AtomicWriteFile, which checks the flush and the close: exit 2 and no overlay folder.
#include <catch2/catch.hpp>
#include <filesystem>

#include "test_support.h"

namespace fs = std::filesystem;
using namespace dynref;

TEST_CASE("overlay: a full disk fails loudly and leaves no partial overlays", "[cli]") {
  const std::string dir = test::ScratchDir("overlay_full");
  REQUIRE(test::RunDynref("synth --preset static_xyz --frames 10 --seed 1 --out " + test::Quote(dir + "/seq")).exit_code == 0);
  REQUIRE(test::RunDynref("run --sequence " + test::Quote(dir + "/seq") + " --out " + test::Quote(dir + "/run") +
                          " --trace full --no-progress").exit_code == 0);
  const std::string mnt = dir + "/small";
  fs::create_directories(mnt);
  // A tmpfs just larger than the run folder (in a private mount namespace): the run fits, the
  // overlays (~0.3 MB each) do not.
  const std::string script = "size=$(( $(du -sk " + dir + "/run | cut -f1) + 200 ))k; mount -t tmpfs -o size=$size tmpfs " +
                             mnt + " && cp -r " + dir + "/run " + mnt + "/run && " + test::DynrefExe() + " overlay " +
                             mnt + "/run --frames 0-9; echo exit=$?; echo LISTING; ls -a " + mnt + "/run";
  const test::CommandResult r = test::RunShell("unshare -m sh -c " + test::Quote(script));
  INFO(r.output);
  REQUIRE(r.output.find("exit=") != std::string::npos);  // the mount worked
  CHECK(r.output.find("exit=2") != std::string::npos);
  const size_t listing = r.output.find("LISTING");
  REQUIRE(listing != std::string::npos);
  CHECK(r.output.find("overlays", listing) == std::string::npos);  // no partial folder published
}
