// `dynref trace feature --follow` (ref/trace/README.md "Following a feature") and the map point
// history through OBS associated_map_point_id (trace schema 3), on a hand-written trace.
#include <catch2/catch.hpp>

#include <set>
#include <sstream>

#include "test_support.h"
#include "trace/trace_feature.h"
#include "trace_follow_sample.h"

using namespace dynref::trace;
using dynref::test::Quote;
using dynref::test::RunDynref;

namespace {
std::vector<std::string> ChainIds(const FeatureHistory& h) {
  std::vector<std::string> out;
  for (const ChainEntry& c : h.chain) out.push_back(c.entity);
  return out;
}
std::set<std::string> RowEntities(const FeatureHistory& h) {
  std::set<std::string> out;
  for (const FlatRecord& f : h.rows) out.insert(f.entity);
  return out;
}
std::string FollowTrace(const std::string& name) {
  const std::string path = dynref::test::ScratchDir(name) + "/follow.dtr";
  dynref::test::WriteFollowTrace(path);
  return path;
}
}  // namespace

TEST_CASE("follow: prev_index links over 7 frames, a map point link and a suppressed feature", "[cli]") {
  TraceReader r(FollowTrace("trace_follow_chain"));
  const std::vector<std::string> all = {"f0.10", "f1.11", "f2.12", "f3.13", "f4.14", "f5.15", "f6.16", "mp50"};
  for (const std::string start : {"f3.13", "f4.14", "mp50", "f2.12"}) {
    INFO(start);
    const FeatureHistory h = CollectFollowHistory(r, start);
    CHECK(h.follow);
    CHECK(ChainIds(h) == all);
    // frames ascending, file order within; distractors absent
    for (size_t i = 1; i < h.rows.size(); ++i) CHECK(h.rows[i - 1].frame <= h.rows[i].frame);
    const std::set<std::string> e = RowEntities(h);
    CHECK(e.count("mp50@f2"));   // the map point's residual
    CHECK(e.count("f5.15"));     // the suppressed feature
    CHECK_FALSE(e.count("f3.1"));
    CHECK_FALSE(e.count("f2.0"));
    CHECK_FALSE(e.count("f1.99"));
    CHECK_FALSE(e.count("mp70@f6"));
    CHECK_FALSE(e.count("f1.50"));      // a sibling: reached only by turning around at f0.10
    CHECK_FALSE(e.count("keypoints"));  // COUNT records are not entities
  }
  // Previous-frame links never turn around: from f6.16 back through mp50 to f2.12 and earlier,
  // not forward again to f3.13 (f2.12's continuation without the map point); from f0.10 forward
  // to both features that name it (f1.11 and the sibling f1.50).
  CHECK(ChainIds(CollectFollowHistory(r, "f6.16")) ==
        std::vector<std::string>{"f0.10", "f1.11", "f2.12", "f5.15", "f6.16", "mp50"});
  CHECK(ChainIds(CollectFollowHistory(r, "f0.10")) ==
        std::vector<std::string>{"f0.10", "f1.11", "f1.50", "f2.12", "f3.13", "f4.14", "f5.15", "f6.16", "mp50"});
  const FeatureHistory h = CollectFollowHistory(r, "f3.13");
  CHECK(h.chain.at(0).via == "prev_index");
  CHECK(h.chain.at(0).from == "f1.11");
  CHECK(h.chain.at(3).via == "start");
  CHECK(h.chain.at(5).via == "map point (OBS)");  // f5.15 reached only through mp50
  CHECK(h.chain.at(5).from == "mp50");
  CHECK(h.chain.at(7).frame == -1);               // a landmark
  int decisions = 0, obs = 0;
  for (const FlatRecord& f : h.rows) {
    decisions += f.type == "decision";
    obs += f.type == "obs";
  }
  CHECK(decisions == 1);
  CHECK(obs == 7);
}

TEST_CASE("follow: line samples, masks through their instance id, residual links of the backbone") {
  TraceReader r(FollowTrace("trace_follow_lines"));
  CHECK(ChainIds(CollectFollowHistory(r, "l3.2")) == std::vector<std::string>{"l0.0", "l1.0", "l3.2", "ml3"});
  CHECK(ChainIds(CollectFollowHistory(r, "ml3")) == std::vector<std::string>{"l0.0", "l1.0", "l3.2", "ml3"});
  CHECK(ChainIds(CollectFollowHistory(r, "i1.2")) == std::vector<std::string>{"i0.2", "i1.2", "i3.2"});
  CHECK(ChainIds(CollectFollowHistory(r, "i1.5")) == std::vector<std::string>{"i1.5"});
  // the distractor chain: f3.1 -> f2.0 (prev_index) and mp60 (map_point input)
  CHECK(ChainIds(CollectFollowHistory(r, "f3.1")) == std::vector<std::string>{"f2.0", "f3.1", "mp60"});
  // an entity without links is a chain of one
  const FeatureHistory lone = CollectFollowHistory(r, "f2.99");
  CHECK(ChainIds(lone) == std::vector<std::string>{"f2.99"});
  CHECK(lone.rows.size() == 1);  // its OBS
  // residual links: a local BA observation of keyframe kf3 (frame 1) and a pose-only one. They are
  // one-hop references (README "Following a feature"): mp70 joins f1.99's chain but does not bring
  // in f6.99; from mp70 both features join.
  const FeatureHistory res = CollectFollowHistory(r, "f1.99");
  CHECK(ChainIds(res) == std::vector<std::string>{"f1.99", "mp70"});
  CHECK(res.chain.at(1).via == "residual (localba.obs)");
  CHECK(RowEntities(res).count("mp70@kf3"));
  CHECK(ChainIds(CollectFollowHistory(r, "f6.99")) == std::vector<std::string>{"f6.99", "mp70"});
  CHECK(ChainIds(CollectFollowHistory(r, "mp70")) == std::vector<std::string>{"f1.99", "f6.99", "mp70"});
  // Only the start's own track brings in a landmark's entities: from f3.70, mp90 brings in f5.70,
  // whose second map point mp91 joins without bringing in f6.71; from f5.70 both do.
  CHECK(ChainIds(CollectFollowHistory(r, "f3.70")) == std::vector<std::string>{"f3.70", "f5.70", "mp90", "mp91"});
  CHECK(ChainIds(CollectFollowHistory(r, "f5.70")) ==
        std::vector<std::string>{"f3.70", "f5.70", "f6.71", "mp90", "mp91"});
}

TEST_CASE("map point history (no --follow) includes the suppressed feature through associated_map_point_id") {
  TraceReader r(FollowTrace("trace_follow_mp"));
  const FeatureHistory h = CollectFeatureHistory(r, "mp50");
  const std::set<std::string> e = RowEntities(h);
  CHECK(e == std::set<std::string>{"f2.12", "f5.15", "mp50@f2"});
  bool decision = false;
  for (const FlatRecord& f : h.rows) decision = decision || (f.type == "decision" && f.entity == "f5.15");
  CHECK(decision);
}

TEST_CASE("trace feature --follow prints the chain then the records, --plot writes a PNG", "[cli]") {
  const std::string trace = FollowTrace("trace_follow_cli");
  const std::string png = dynref::test::ScratchDir("trace_follow_cli_png") + "/chain.png";
  const auto out = RunDynref("trace feature " + Quote(trace) + " f3.13 --follow --plot " + Quote(png));
  INFO(out.output);
  CHECK(out.exit_code == 0);
  CHECK(out.output.rfind("# chain of f3.13: 8 entities (frame -> entity, link)\n# 0 -> f0.10 (prev_index, from f1.11)\n", 0) == 0);
  CHECK(out.output.find("# 5 -> f5.15 (map point (OBS), from mp50)\n") != std::string::npos);
  CHECK(out.output.find("# - -> mp50 (map point (OBS), from f2.12)\n") != std::string::npos);
  CHECK(out.output.find("\nframe,type,stage,kind,entity,occurrence,fields\n0,") != std::string::npos);
  CHECK(out.output.find("5,decision,mgd.probability,feature,f5.15,0,kept=0 reason=p>tau_dyn\n") != std::string::npos);
  const std::string bytes = dynref::test::ReadFileBytes(png);
  REQUIRE(bytes.size() > 1000);
  CHECK(bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0);
  // The same command twice: byte-identical output and image.
  const std::string png2 = dynref::test::ScratchDir("trace_follow_cli_png2") + "/chain.png";
  const auto again = RunDynref("trace feature " + Quote(trace) + " f3.13 --follow --plot " + Quote(png2));
  CHECK(again.output == out.output);
  CHECK(dynref::test::ReadFileBytes(png2) == bytes);
  // Without --follow: no chain section, frame 3 only.
  const auto plain = RunDynref("trace feature " + Quote(trace) + " f3.13");
  CHECK(plain.output.rfind("frame,type,stage,kind,entity,occurrence,fields\n3,", 0) == 0);
  CHECK(plain.output.find("\n2,") == std::string::npos);
}
