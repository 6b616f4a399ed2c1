// Schema 2 checksums (issue 20 item 8): flipped bits anywhere in a trace are refused with
// "corrupt", naming the frame when the damage is in a frame block; schema 1 traces still read.
#include <catch2/catch.hpp>

#include <fstream>
#include <iterator>

#include "core/rng.h"
#include "test_support.h"
#include "trace/trace_dump.h"
#include "trace/trace_reader.h"
#include "trace_sample.h"

using namespace dynref::trace;
using dynref::test::RunDynref;

namespace {
void Spit(const std::string& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}
// Reads everything a diff reads: preamble, header, footer and every frame block.
void ReadAll(const std::string& path) {
  TraceReader r(path);
  for (size_t g = 0; g < r.groups().size(); ++g) r.ReadGroup(g);
}
}  // namespace

TEST_CASE("every single-bit flip of a schema-2 trace is refused, never read silently") {
  const std::string dir = dynref::test::ScratchDir("trace_bitflips");
  const std::string path = dir + "/a.dtr";
  dynref::test::WriteSampleTrace(path);
  REQUIRE_NOTHROW(ReadAll(path));
  const std::string bytes = dynref::test::ReadFileBytes(path);
  dynref::Rng rng(20, "test.trace_bitflips");
  int refused = 0, flips = 0;
  // Every byte once (a random bit of it) plus 200 random (byte, bit) pairs.
  for (size_t i = 0; i < bytes.size() + 200; ++i) {
    const size_t byte = i < bytes.size() ? i : rng.UniformInt(0, static_cast<int>(bytes.size()) - 1);
    const int bit = rng.UniformInt(0, 7);
    std::string flipped = bytes;
    flipped[byte] = static_cast<char>(flipped[byte] ^ (1 << bit));
    Spit(dir + "/f.dtr", flipped);
    ++flips;
    try {
      ReadAll(dir + "/f.dtr");
      FAIL_CHECK("flip of bit " << bit << " at byte " << byte << " of " << bytes.size()
                                << " read silently");
    } catch (const TraceError&) {
      ++refused;
    }
  }
  CHECK(refused == flips);
}

TEST_CASE("a flipped block names its frame, a changed header config is refused by diff", "[cli]") {
  const std::string dir = dynref::test::ScratchDir("trace_corrupt_frame");
  const std::string path = dir + "/a.dtr";
  dynref::test::WriteSampleTrace(path);
  uint64_t inside_frame2 = 0;
  {
    TraceReader r(path);
    for (const auto& g : r.groups())
      if (g.frame == 2) inside_frame2 = g.offset + 12;  // inside the FRAME timestamp
  }
  REQUIRE(inside_frame2 > 0);
  std::string bytes = dynref::test::ReadFileBytes(path);
  bytes[inside_frame2] = static_cast<char>(bytes[inside_frame2] ^ 0x01);  // a float, still decodes
  Spit(dir + "/frame2.dtr", bytes);
  const auto d = RunDynref("diff '" + path + "' '" + dir + "/frame2.dtr'");
  CHECK(d.exit_code == 2);
  CHECK(d.output.find("frame2.dtr: corrupt at frame 2") != std::string::npos);
  CHECK(RunDynref("trace dump '" + dir + "/frame2.dtr'").exit_code == 2);

  // The config text in the header: same length, one letter changed (schema 1 gave MATCH).
  std::string header = dynref::test::ReadFileBytes(path);
  const size_t at = header.find("{\"a\":1}");
  REQUIRE(at != std::string::npos);
  header[at + 5] = '2';
  Spit(dir + "/header.dtr", header);
  const auto h = RunDynref("diff '" + path + "' '" + dir + "/header.dtr'");
  CHECK(h.exit_code == 2);
  CHECK(h.output.find("header.dtr: corrupt: header checksum mismatch") != std::string::npos);
}

TEST_CASE("schema 1 traces (no checksums) still read, dump and diff", "[cli]") {
  const std::string v1 = dynref::test::SourcePath("tests/data/trace_v1/orb_30f_schema1.dtr");
  TraceReader r(v1);
  CHECK(r.schema_version() == 1);
  CHECK(r.groups().size() == 30);
  REQUIRE_NOTHROW(ReadAll(v1));
  const auto self = RunDynref("diff '" + v1 + "' '" + v1 + "'");
  CHECK(self.exit_code == 0);
  const auto head = RunDynref("trace dump '" + v1 + "' --header");
  CHECK(head.exit_code == 0);
  CHECK(head.output.find("schema_version,1") != std::string::npos);
}
