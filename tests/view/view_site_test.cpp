// `dynref view` (issue 36): the site of a run opened in headless Chromium (Debian's chromium,
// installed by scripts/install-deps.sh --tests): the page's history of an entity equals
// `dynref trace feature` record for record; a click on a feature opens its history; a screenshot
// of the page is written to the test's folder (build/test_scratch/..., kept with
// DYNREF_KEEP_SCRATCH=1).
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.h"

namespace fs = std::filesystem;
using dynref::test::Quote;
using dynref::test::RunDynref;
using dynref::test::RunShell;

namespace {

std::string Chromium() {
  for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (fs::exists(p)) return p;
  return "";
}

std::string ChromiumFlags(const std::string& profile) {
  return " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking "
         "--disable-component-update --disable-sync --allow-file-access-from-files --virtual-time-budget=20000 "
         "--user-data-dir=" + Quote(profile);
}

std::string Unescape(std::string s) {
  const std::vector<std::pair<std::string, std::string>> entities = {{"&lt;", "<"}, {"&gt;", ">"}, {"&quot;", "\""}, {"&amp;", "&"}};
  for (const auto& [from, to] : entities)
    for (size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size())) s.replace(p, from.size(), to);
  return s;
}

// The page's self-check output (#selftest) after it showed `query` (URL parameters).
nlohmann::json PageHistory(const std::string& site, const std::string& query, const std::string& scratch) {
  const std::string chromium = Chromium();
  REQUIRE_FALSE(chromium.empty());  // CI installs chromium (scripts/install-deps.sh --tests)
  const std::string url = "file://" + fs::absolute(site).string() + "/index.html?" + query + "&selftest=1";
  const auto r = RunShell(chromium + ChromiumFlags(scratch + "/profile") + " --dump-dom " + Quote(url) + " 2>/dev/null");
  const std::string& dom = r.output;
  const size_t open = dom.find("<pre id=\"selftest\" hidden=\"\">");
  REQUIRE(open != std::string::npos);
  const size_t start = dom.find('>', open) + 1, end = dom.find("</pre>", start);
  const std::string text = Unescape(dom.substr(start, end - start));
  INFO(text.substr(0, 500));
  REQUIRE_FALSE(text.empty());
  return nlohmann::json::parse(text);
}

// `dynref trace feature` rows: frame,type,stage,kind,entity,occurrence,"name=value ...".
struct Row {
  std::string frame, type, stage, kind, entity, occurrence;
  std::vector<std::pair<std::string, std::string>> fields;
};
// `chain` (with --follow): the "# <frame> -> <entity> (<via>, from <entity>)" lines.
std::vector<Row> CliHistory(const std::string& run, const std::string& id, bool follow = false,
                            std::vector<std::string>* chain = nullptr) {
  const auto r = RunDynref("trace feature " + Quote(run) + " " + id + (follow ? " --follow" : "") + " 2>/dev/null");
  REQUIRE(r.exit_code == 0);
  std::vector<Row> rows;
  std::istringstream in(r.output);
  std::string line;
  while (std::getline(in, line)) {
    if (chain && line.rfind("# ", 0) == 0 && line.rfind("# chain of ", 0) != 0 && line.find(" -> ") != std::string::npos)
      chain->push_back(line);  // one line per linked entity, not the chain's header line
    if (line.empty() || line[0] == '#' || line.rfind("frame,", 0) == 0) continue;
    std::vector<std::string> cols;
    std::string cur;
    bool quoted = false;
    for (size_t i = 0; i < line.size(); ++i) {
      const char c = line[i];
      if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') cur += '"', ++i;
      else if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) cols.push_back(cur), cur.clear();
      else cur += c;
    }
    cols.push_back(cur);
    REQUIRE(cols.size() == 7);
    Row row{cols[0], cols[1], cols[2], cols[3], cols[4], cols[5], {}};
    std::istringstream fs(cols[6]);
    std::string kv;
    while (fs >> kv) row.fields.emplace_back(kv.substr(0, kv.find('=')), kv.substr(kv.find('=') + 1));
    rows.push_back(row);
  }
  return rows;
}

std::string JsonText(const nlohmann::json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); }

// `text` (a number trace feature prints) rounded as the page writes it (ref/view/packed.h).
double Rounded(const std::string& text, int digits) {
  const double v = std::strtod(text.c_str(), nullptr);
  if (digits >= 17) return v;
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.*g", digits, v);
  return std::strtod(buf, nullptr);
}

// Record for record: same keys, exact fields equal as text, numbers equal as doubles once rounded
// to the site's significant digits (17: exact).
void CheckSameHistory(const std::vector<Row>& cli, const nlohmann::json& page, int digits = 17) {
  const nlohmann::json& rows = page.at("rows");
  REQUIRE(rows.size() == cli.size());
  for (size_t i = 0; i < cli.size(); ++i) {
    const nlohmann::json& p = rows[i];
    INFO("row " << i << ": " << p.dump());
    CHECK(JsonText(p[0]) == cli[i].frame);
    CHECK(p[1] == cli[i].type);
    CHECK(p[2] == cli[i].stage);
    CHECK(p[3] == cli[i].kind);
    CHECK(p[4] == cli[i].entity);
    CHECK(JsonText(p[5]) == cli[i].occurrence);
    REQUIRE(p[6].size() == cli[i].fields.size());
    for (const auto& [name, text] : cli[i].fields) {
      REQUIRE(p[6].contains(name));
      const nlohmann::json& v = p[6][name];
      if (v.is_number()) CHECK(v.get<double>() == Rounded(text, digits));
      else CHECK(v.get<std::string>() == text);
    }
  }
}

}  // namespace

TEST_CASE("view end to end: golden mgd_30f mp34's history in Chromium equals dynref trace feature, suppression included", "[view][cli]") {
  const std::string dir = dynref::test::ScratchDir("view_golden_mp34");
  const std::string golden = dynref::test::SourcePath("golden/mgd_30f");
  const auto v = RunDynref("view " + Quote(golden) + " --digits 17 --no-overlays --out " + Quote(dir + "/site"));
  INFO(v.output);
  REQUIRE(v.exit_code == 0);
  const std::vector<Row> cli = CliHistory(golden, "mp34");
  std::string suppressed;  // mp34's feature in frame 1, rejected by mgd.probability
  for (const Row& r : cli)
    if (r.frame == "1" && r.type == "decision" && r.fields.size() > 0 && r.fields[0].second == "0") suppressed = r.entity;
  CHECK(!suppressed.empty());
  const nlohmann::json page = PageHistory(dir + "/site", "entity=mp34&follow=0", dir);
  CheckSameHistory(cli, page);
  // The data files were decoded by the page's workers (view.js unlzmaOffThread), not by the page.
  CHECK(page.value("decoder", "") == "worker");

  SECTION("data files of 7 frames (chunk boundaries inside mp34's frames): the same history") {
    // 30 frames in files of 7: frames 0-6, 7-13, ..., 28-29; the page must find each frame's
    // place in its file (site_data.cpp ChunkWriter, view.js frameOf).
    const auto v7 = RunDynref("view " + Quote(golden) + " --digits 17 --no-overlays --chunk-frames 7 --out " + Quote(dir + "/site7"));
    REQUIRE(v7.exit_code == 0);
    CHECK(fs::exists(dir + "/site7/data/r0/c4.js"));
    CHECK_FALSE(fs::exists(dir + "/site7/data/r0/c5.js"));
    // Five data files: the history reads them in order while a worker decodes the next one.
    const nlohmann::json page7 = PageHistory(dir + "/site7", "entity=mp34&follow=0", dir);
    CheckSameHistory(cli, page7);
    CHECK(page7.value("decoder", "") == "worker");
    // --threads 3 compresses the 5 chunks at once (site_data.cpp ChunkWriter): every file the same.
    const auto t3 = RunDynref("view " + Quote(golden) + " --digits 17 --no-overlays --chunk-frames 7 --threads 3 --out " +
                              Quote(dir + "/site7t"));
    REQUIRE(t3.exit_code == 0);
    int files = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir + "/site7")) {
      if (!e.is_regular_file()) continue;
      const std::string rel = fs::relative(e.path(), dir + "/site7").string();
      INFO(rel);
      CHECK(dynref::test::ReadFileBytes(e.path().string()) == dynref::test::ReadFileBytes(dir + "/site7t/" + rel));
      ++files;
    }
    CHECK(files >= 8);  // index, scripts, summary, links, 5 chunks
  }

  SECTION("the followed chain of the suppressed feature equals trace feature --follow, link for link") {
    REQUIRE(!suppressed.empty());
    std::vector<std::string> chain;
    const std::vector<Row> followed = CliHistory(golden, suppressed, true, &chain);
    const nlohmann::json fpage = PageHistory(dir + "/site", "entity=" + suppressed + "&follow=1", dir);
    CHECK(fpage.at("follow") == true);
    CheckSameHistory(followed, fpage);
    std::vector<std::string> page_chain;
    for (const nlohmann::json& c : fpage.at("chain")) {
      const int64_t frame = c[0].get<int64_t>();
      const std::string from = c[3];
      page_chain.push_back("# " + (frame >= 0 ? std::to_string(frame) : std::string("-")) + " -> " + c[1].get<std::string>() +
                           " (" + c[2].get<std::string>() + (from.empty() ? "" : ", from " + from) + ")");
    }
    CHECK(page_chain == chain);
    CHECK(chain.size() > 3);  // frames before and after, and the map point
  }

  SECTION("mp34 followed: the page's chain equals trace feature --follow, residual links one hop") {
    // mp34's chain has entities reached through residual links (ref/trace/README.md "Following a
    // feature": one-hop references); page and CLI must apply the same rule.
    std::vector<std::string> chain;
    const std::vector<Row> followed = CliHistory(golden, "mp34", true, &chain);
    const nlohmann::json fpage = PageHistory(dir + "/site", "entity=mp34&follow=1", dir);
    CheckSameHistory(followed, fpage);
    CHECK(fpage.at("chain").size() == chain.size());
    size_t residual = 0;
    for (const std::string& line : chain) residual += line.find("(residual (") != std::string::npos;
    CHECK(residual > 0);
  }
}

TEST_CASE("view end to end: a 30-frame mgd run, a click on a feature opens its history as trace feature, screenshot kept", "[view][slow][cli]") {
  const std::string dir = dynref::test::ScratchDir("view_mgd_click");
  REQUIRE(RunDynref("synth --preset walking_xyz --seed 1 --frames 30 --detections yolo-like --out " + Quote(dir + "/seq")).exit_code == 0);
  REQUIRE(RunDynref("run --method mgd --sequence " + Quote(dir + "/seq") + " --detections " + Quote(dir + "/seq/detections/yolo-like") +
                    " --trace full --out " + Quote(dir + "/run")).exit_code == 0);
  const auto v = RunDynref("view " + Quote(dir + "/run") + " --out " + Quote(dir + "/site"));
  INFO(v.output);
  REQUIRE(v.exit_code == 0);
  CHECK(fs::exists(dir + "/site/img/r0_10.jpg"));
  // A suppressed feature of frame 10: click at its pixel.
  const auto d = RunDynref("trace dump " + Quote(dir + "/run") + " --frame 10 --format jsonl");
  REQUIRE(d.exit_code == 0);
  std::string entity;
  std::istringstream in(d.output);
  std::string line;
  std::map<std::string, std::pair<double, double>> uv;
  while (std::getline(in, line)) {
    const nlohmann::json j = nlohmann::json::parse(line);
    if (j["type"] == "obs") uv[j["entity"]] = {j["fields"]["u"].get<double>(), j["fields"]["v"].get<double>()};
    if (entity.empty() && j["type"] == "decision" && j["kind"] == "feature" && j["fields"]["kept"] == "0") entity = j["entity"];
  }
  REQUIRE(!entity.empty());
  REQUIRE(uv.count(entity));
  const auto [u, v2] = uv[entity];
  const nlohmann::json page = PageHistory(dir + "/site", "follow=0&frame=10&click=" + std::to_string(u) + "," + std::to_string(v2), dir);
  // The click may land on a neighbour within a pixel: compare with the entity the page chose.
  const std::string clicked = page.at("entity");
  CheckSameHistory(CliHistory(dir + "/run", clicked), page, 6);  // the default --digits 6
  // Its followed chain, as trace feature --follow (numbers to 6 digits).
  std::vector<std::string> chain;
  const std::vector<Row> followed = CliHistory(dir + "/run", clicked, true, &chain);
  const nlohmann::json fpage = PageHistory(dir + "/site", "entity=" + clicked + "&follow=1", dir);
  CheckSameHistory(followed, fpage, 6);
  CHECK(fpage.at("chain").size() == chain.size());
  // Size bound (README "Size"): data and overlays per frame of a --trace full mgd run.
  uint64_t data = 0, images = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir + "/site"))
    if (e.is_regular_file()) (e.path().extension() == ".jpg" ? images : data) += e.file_size();
  INFO("data " << data << " B, images " << images << " B for 30 frames");
  // A regression bound at today's size with ~12 % margin (ref/view/README.md "Size": 115 KB of
  // data and 24 KB of overlay per frame measured on this run, one LZMA file for the 30 frames;
  // 152 KB with zlib per frame, 185 KB with basE91, 247 KB before the packed columns).
  CHECK(data / 30 < 130 * 1024);
  CHECK(images / 30 < 27 * 1024);
  // Screenshot of the page with that history open (kept beside the test's outputs).
  const std::string url = "file://" + fs::absolute(dir + "/site").string() + "/index.html?frame=10&follow=1&entity=" + clicked;
  const std::string png = dir + "/viewer_screenshot.png";
  RunShell(Chromium() + ChromiumFlags(dir + "/profile2") + " --window-size=1500,1100 --screenshot=" + Quote(png) + " " + Quote(url) + " 2>/dev/null");
  CHECK(fs::exists(png));
  CHECK(fs::file_size(png) > 20000);
}

TEST_CASE("view: bad input names what is wrong", "[view][cli]") {
  const std::string dir = dynref::test::ScratchDir("view_bad_input");
  dynref::test::ExpectBadInput("view " + Quote(dir + "/none") + " --out " + Quote(dir + "/site"), "trace");
  fs::create_directories(dir + "/mine");
  dynref::test::WriteText(dir + "/mine/keep.txt", "mine");
  dynref::test::ExpectBadInput("view " + Quote(dynref::test::SourcePath("golden/mgd_30f")) + " --out " + Quote(dir + "/mine"),
                               "not written by dynref view");
  CHECK(fs::exists(dir + "/mine/keep.txt"));
}
