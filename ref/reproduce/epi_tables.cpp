#include "reproduce/epi_tables.h"

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include <CLI/CLI.hpp>

#include "core/atomic_file.h"
#include "core/cpu_clock.h"
#include "core/error.h"
#include "core/se3.h"
#include "core/version.h"
#include "dynamic/epi/stages.h"
#include "features/mnn2.h"
#include "io/sequence.h"
#include "pipeline/method_config.h"
#include "reproduce/arg_checks.h"
#include "reproduce/paper_table.h"
#include "reproduce/report_format.h"
#include "reproduce/report_plots.h"
#include "reproduce/workspace.h"

namespace fs = std::filesystem;

namespace dynref::reproduce {
namespace {

cv::Mat Grey(const Sequence& s, size_t k) {
  cv::Mat g;
  cv::cvtColor(LoadRgb(s, s.frames[k]), g, cv::COLOR_BGR2GRAY);
  return g;
}

SE3 GtPose(const Sequence& s, size_t k) {  // T_wc at the frame's stamp (synthetic: exact stamps)
  for (const StampedPose& p : s.groundtruth)
    if (std::abs(p.stamp - s.frames[k].rgb_stamp) < 1e-4) return p.T_wc;
  throw InputError(s.groundtruth_path, "no ground-truth pose at " + s.frames[k].rgb_stamp_text);
}

struct Features {
  std::vector<cv::KeyPoint> kp;
  cv::Mat desc;
};

Features Detect(const std::string& kind, const cv::Mat& grey, int n) {
  Features f;
  cv::Ptr<cv::Feature2D> d;
  if (kind == "ORB") d = cv::ORB::create(n);
  else d = cv::SIFT::create(n);
  d->detectAndCompute(grey, cv::noArray(), f.kp, f.desc);
  return f;
}

struct MatchStats {
  int64_t matches = 0, verifiable = 0, correct = 0, pairs = 0;
  double ms = 0;
};

// Is match (a in frame 1, b in frame 2) correct: back-project a with frame 1's depth, move by the
// ground-truth poses, project into frame 2; verifiable when the point is in front, inside and not
// occluded in frame 2 (its depth there within 5 % + 2 cm).
int Verify(const cv::Point2f& a, const cv::Point2f& b, const cv::Mat& depth1, const cv::Mat& depth2, const SE3& T_c2_c1,
           const Camera& cam, double gate) {
  const int x = int(std::lround(a.x)), y = int(std::lround(a.y));
  if (x < 0 || y < 0 || x >= depth1.cols || y >= depth1.rows) return -1;
  const double z = depth1.at<float>(y, x);
  if (!(z > 0)) return -1;
  const Eigen::Vector3d X1((a.x - cam.cx) / cam.fx * z, (a.y - cam.cy) / cam.fy * z, z);
  const Eigen::Vector3d X2 = T_c2_c1 * X1;
  if (!(X2.z() > 0.05)) return -1;
  const double u = cam.fx * X2.x() / X2.z() + cam.cx, v = cam.fy * X2.y() / X2.z() + cam.cy;
  const int ux = int(std::lround(u)), vy = int(std::lround(v));
  if (ux < 0 || vy < 0 || ux >= depth2.cols || vy >= depth2.rows) return -1;
  const double z2 = depth2.at<float>(vy, ux);
  if (!(z2 > 0) || std::abs(z2 - X2.z()) > 0.05 * X2.z() + 0.02) return -1;  // occluded or no depth
  return std::hypot(u - b.x, v - b.y) < gate ? 1 : 0;
}

void EpiCheckArgs(const EpiTableArgs& a) {
  if (a.table != "table1" && a.table != "table2") throw InputError("table", "unknown table '" + a.table + "'");
  if (a.frames < 10) throw InputError("--frames", "need at least 10 frames, got " + std::to_string(a.frames));
  if (a.gap < 1 || a.gap >= a.frames) throw InputError("--gap", "must be in 1..frames-1");
  if (a.features < 10) throw InputError("--features", "must be >= 10");
  CheckSeedList(a.seeds);
  CheckReportPaths(a.out, a.work);
}

}  // namespace

namespace {

// The shared workspace of one epi feature table: arguments, the paper's table, Module A's options.
struct EpiRun {
  const EpiTableArgs& a;
  PaperTable paper;
  epi::EnhanceStageOptions enhance;
  std::string plot_png;  // beside the report
  explicit EpiRun(const EpiTableArgs& args) : a(args) {}
  // The sequence of `preset` (synthesised once per lighting / blur variant, no detections).
  Sequence OpenPreset(uint64_t seed, const std::string& preset, bool low_light, bool blur) const {
    const std::string variant = std::string(low_light ? "lowlight" : "normal") + (blur ? "-blur" : "");
    Workspace ws(SeedWorkDir(a.work, seed) + "/" + variant, {a.frames, seed, "none", blur, low_light}, a.reuse);
    return OpenSequence(ws.EnsureSequence(preset));
  }
};

struct Typology {
  std::string name, preset;
  bool low1, low2, blur;
};
const std::vector<Typology>& Typologies() {
  static const std::vector<Typology> typ = {{"Light change", "static_xyz", false, true, false},
                                            {"Rotational change", "static_rpy", false, false, false},
                                            {"Perspective change", "static_halfsphere", false, false, false},
                                            {"Motion blur", "static_xyz", false, false, true},
                                            {"Low light (both frames dark)", "static_xyz", true, true, false}};
  return typ;
}
const std::vector<std::pair<std::string, std::string>>& Algorithms() {
  static const std::vector<std::pair<std::string, std::string>> algos = {
      {"ORB", "BF"}, {"ORB", "MNN2"}, {"SIFT", "BF"}, {"SIFT", "MNN2"}};
  return algos;
}

// What table2 measures: per typology and algorithm the match counts, and the descriptor distances
// of verifiable BF matches, correct and wrong, per extractor (all typologies but the light change):
// what the backbone's gates (features/descriptor.h) are read from.
struct Matching {
  std::map<std::string, std::vector<MatchStats>> stats;
  std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> distances;
};

void EpiWriteIntro(const EpiRun& r, std::ostringstream& md) {
  const EpiTableArgs& a = r.a;
  const std::string cmd = "dynref reproduce epi-" + a.table + " --frames " + std::to_string(a.frames) + " --seeds " +
                          SeedListText(a.seeds) + (a.table == "table2" ? " --gap " + std::to_string(a.gap) + " --features " +
                                                                          std::to_string(a.features) : "");
  md << "# Enhanced-epipolar SLAM (seed 004) Table " << (a.table == "table1" ? "1" : "2")
     << " analogue on synthetic static scenes\n\nWritten by `" << cmd << "` (dynref " << DYNREF_VERSION << ", commit "
     << DYNREF_GIT_COMMIT << "). Do not edit by hand. Seeds " << SeedListText(a.seeds) << ", " << a.frames
     << " frames per sequence (`dynref synth --preset P --frames " << a.frames << " --seed S [--low-light] [--blur]`). "
     << "The paper's learned detector (improved ZippyPoint) is not available to dynref (issue 17 Module B): "
     << "OpenCV SIFT is the float-descriptor path here, the paper's values are printed beside for reference only.\n\n";
}

// Table 1: keypoints per frame, raw vs enhanced (BOA tuned on each sequence's first frame).
void WriteKeypointTable(const EpiRun& r, std::ostringstream& md) {
  const EpiTableArgs& a = r.a;
  const PaperTable& paper = r.paper;
  const std::string& plot_png = r.plot_png;
  const auto sequence = [&r](uint64_t seed, const std::string& preset, bool low, bool blur) {
    return r.OpenPreset(seed, preset, low, blur);
  };
  const epi::EnhanceStageOptions& enhance = r.enhance;
  md << "## Keypoints per frame (mean over frames and seeds), raw grey vs Module A enhanced\n\n"
     << "ORB: OpenCV ORB, FAST threshold 20, no count cap; SIFT: OpenCV SIFT defaults, no cap.\n\n"
     << "| Sequence | ORB raw | ORB + A | SIFT raw | SIFT + A |\n|---|---|---|---|---|\n";
  std::vector<std::string> groups;
  std::vector<render::BarSeries> series = {{"ORB raw", {}, {}, render::SeriesColour(4)},
                                           {"ORB + A", {}, {}, Lighter(render::SeriesColour(4))},
                                           {"SIFT raw", {}, {}, render::SeriesColour(5)},
                                           {"SIFT + A", {}, {}, Lighter(render::SeriesColour(5))}};
  for (const auto& [preset, low] : std::vector<std::pair<std::string, bool>>{
           {"static_xyz", false}, {"static_xyz", true}, {"walking_xyz", false}, {"walking_xyz", true}}) {
    double sums[4] = {0, 0, 0, 0};
    int64_t n = 0;
    for (uint64_t seed : a.seeds) {
      const Sequence s = sequence(seed, preset, low, false);
      epi::SequenceEnhancer enhancer(enhance);
      for (size_t k = 0; k < s.frames.size(); ++k) {
        const cv::Mat g = Grey(s, k);
        const cv::Mat e = enhancer.Enhance(g).grey8;
        sums[0] += double(Detect("ORB", g, 1000000).kp.size());
        sums[1] += double(Detect("ORB", e, 1000000).kp.size());
        sums[2] += double(Detect("SIFT", g, 0).kp.size());
        sums[3] += double(Detect("SIFT", e, 0).kp.size());
        ++n;
      }
    }
    md << "| " << preset << (low ? " --low-light" : "") << " |";
    for (double v : sums) md << " " << Num(v / double(std::max<int64_t>(1, n)), 0) << " |";
    md << "\n";
    groups.push_back(preset + (low ? " dark" : ""));
    for (size_t i = 0; i < 4; ++i) series[i].value.push_back(sums[i] / double(std::max<int64_t>(1, n)));
  }
  render::BarChartOptions bo;
  bo.title = "Keypoints per frame, raw vs Module A enhanced (mean over frames and seeds " + SeedListText(a.seeds) + ")";
  bo.y_label = "keypoints per frame";
  bo.log_y = true;
  PlotBars(groups, series, bo, plot_png);
  md << "\n![keypoints per frame](" << fs::path(plot_png).filename().string() << ")\n";
  md << "\nPaper Table 1 (one weak-texture image, points extracted): ORB " << Num(paper.Cell("Extracting Points", "ORB"), 0)
     << ", SuperPoint " << Num(paper.Cell("Extracting Points", "Superpoint [27]"), 0) << ", XFeat "
     << Num(paper.Cell("Extracting Points", "XFeat [44]"), 0) << ", improved ZippyPoint "
     << Num(paper.Cell("Extracting Points", "Improvements to Zippypoint"), 0) << ".\n";
}

// Table 2: every typology's frame pairs matched by every algorithm, checked against the truth.
Matching MeasureMatching(const EpiRun& r) {
  const EpiTableArgs& a = r.a;
  const auto& typ = Typologies();
  const auto& algos = Algorithms();
  const auto sequence = [&r](uint64_t seed, const std::string& preset, bool low, bool blur) {
    return r.OpenPreset(seed, preset, low, blur);
  };
  Matching out;
  auto& stats = out.stats;
  auto& distances = out.distances;
  for (const Typology& t : typ) {
    stats[t.name].resize(algos.size());
    for (uint64_t seed : a.seeds) {
      const Sequence s1 = sequence(seed, t.preset, t.low1, t.blur);
      const Sequence s2 = t.low2 == t.low1 ? s1 : sequence(seed, t.preset, t.low2, t.blur);
      const Camera& cam = s1.camera;
      for (int k = 0; k + a.gap < int(s1.frames.size()); k += a.gap) {
        const size_t k1 = size_t(k), k2 = size_t(k + a.gap);
        const cv::Mat g1 = Grey(s1, k1), g2 = Grey(s2, k2);
        const cv::Mat d1 = LoadDepthMeters(s1, s1.frames[k1]), d2 = LoadDepthMeters(s2, s2.frames[k2]);
        const SE3 T21 = GtPose(s2, k2).inverse() * GtPose(s1, k1);
        for (size_t m = 0; m < algos.size(); ++m) {
          const double t0 = ThreadCpuMs();
          const Features f1 = Detect(algos[m].first, g1, a.features), f2 = Detect(algos[m].first, g2, a.features);
          const std::vector<features::DescriptorMatch> ms =
              algos[m].second == "BF" ? features::MatchNearest(f1.desc, f2.desc)
                                      : features::MatchMnn2(f1.desc, f2.desc, features::Mnn2Options{});
          MatchStats& st = stats[t.name][m];
          st.ms += ThreadCpuMs() - t0;
          ++st.pairs;
          for (const features::DescriptorMatch& dm : ms) {
            ++st.matches;
            const int v = Verify(f1.kp[size_t(dm.i)].pt, f2.kp[size_t(dm.j)].pt, d1, d2, T21, cam, a.correct_px);
            if (v < 0) continue;
            ++st.verifiable;
            st.correct += v;
            if (algos[m].second == "BF" && t.low1 == t.low2) {
              auto& d = distances[algos[m].first];
              (v ? d.first : d.second).push_back(dm.distance);
            }
          }
        }
      }
    }
  }
  return out;
}

void WriteMatchingTable(const EpiRun& r, Matching& mt, std::ostringstream& md) {
  const EpiTableArgs& a = r.a;
  const auto& typ = Typologies();
  const auto& algos = Algorithms();
  auto& stats = mt.stats;
  const std::string& plot_png = r.plot_png;
  md << "## Matching of frame pairs (k, k + " << a.gap << "), " << a.features
     << " features per image, summed over pairs and seeds\n\n"
     << "correct = the matched keypoint lies within " << Short(a.correct_px)
     << " px of the exact correspondence (frame 1 depth + ground-truth poses); precision = correct / verifiable "
     << "(matches whose frame-1 keypoint has depth and is visible, unoccluded, in frame 2); ms = CPU per pair for "
     << "detection, description and matching (one core). No RANSAC after matching (the paper applies one).\n\n"
     << "| Typology | Algorithm | pairs | matches | verifiable | correct | precision % | ms / pair |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  for (const Typology& t : typ)
    for (size_t m = 0; m < algos.size(); ++m) {
      const MatchStats& st = stats[t.name][m];
      md << "| " << t.name << " | " << algos[m].first << " + " << algos[m].second << " | " << st.pairs << " | "
         << st.matches << " | " << st.verifiable << " | " << st.correct << " | " << Pct(st.correct, st.verifiable)
         << " | " << Num(st.ms / double(std::max<int64_t>(1, st.pairs)), 1) << " |\n";
    }
  std::vector<std::string> groups;
  std::vector<render::BarSeries> series;
  for (size_t m = 0; m < algos.size(); ++m)
    series.push_back({algos[m].first + " + " + algos[m].second, {}, {},
                      m % 2 ? render::SeriesColour(4 + m / 2) : Lighter(render::SeriesColour(4 + m / 2))});
  for (const Typology& t : typ) {
    groups.push_back(t.name.substr(0, t.name.find(' ')));
    for (size_t m = 0; m < algos.size(); ++m) {
      const MatchStats& st = stats[t.name][m];
      series[m].value.push_back(st.verifiable ? 100.0 * double(st.correct) / double(st.verifiable) : std::nan(""));
    }
  }
  render::BarChartOptions bo;
  bo.title = "Matching precision per typology (seeds " + SeedListText(a.seeds) + "), MNN2 in the darker bars";
  bo.y_label = "precision [%]";
  PlotBars(groups, series, bo, plot_png);
  md << "\n![matching precision](" << fs::path(plot_png).filename().string() << ")\n";
}

void WriteDistanceTable(Matching& mt, std::ostringstream& md) {
  auto& distances = mt.distances;
  md << "\n## Descriptor distance of correct and wrong nearest neighbours (BF, verifiable matches, all typologies "
        "but the light change)\n\nORB: Hamming bits of 256; SIFT: squared L2 of unit rows (in [0, 2] for SIFT's "
        "non-negative rows). The backbone's gates for `features: sift` (ref/features/sift_extractor.cpp) are read from "
        "this table where ORB-SLAM2's bit gates sit for ORB: TH_LOW (50 bits) near the 75th percentile of correct matches, "
        "TH_HIGH (100 bits) above the 95th percentile of wrong ones, relocalisation's 64 bits near the wrong ones' "
        "25th percentile.\n\n"
     << "| extractor | matches | p5 | p25 | p50 | p75 | p95 |\n|---|---|---|---|---|---|---|\n";
  for (auto& [name, d] : distances)
    for (int wrong = 0; wrong < 2; ++wrong) {
      std::vector<double>& v = wrong ? d.second : d.first;
      std::sort(v.begin(), v.end());
      auto q = [&](double f) { return v.empty() ? std::nan("") : v[size_t(f * double(v.size() - 1))]; };
      const int digits = name == "ORB" ? 0 : 3;
      md << "| " << name << (wrong ? " wrong" : " correct") << " | " << v.size() << " | " << Num(q(0.05), digits) << " | "
         << Num(q(0.25), digits) << " | " << Num(q(0.5), digits) << " | " << Num(q(0.75), digits) << " | "
         << Num(q(0.95), digits) << " |\n";
    }
}

void WritePaperTable2(const PaperTable& paper, std::ostringstream& md) {
  md << "\n## Paper Table 2 (real image pairs, 500 features, RANSAC)\n\n| Typology | Algorithm | correct pairs | accuracy % | time s |\n|---|---|---|---|---|\n";
  for (const std::vector<std::string>& c : paper.ordered)  // rows share their first cell (image number)
    if (c.size() >= 6) md << "| " << c[1] << " | " << c[2] << " | " << c[3] << " | " << c[4] << " | " << c[5] << " |\n";
}

}  // namespace

int RunEpiTable(const EpiTableArgs& a) {
  EpiCheckArgs(a);
  MakeReportFolders(a.out, a.work);
  EpiRun r(a);
  r.paper = ReadPaperTable(PaperTableDir() + "/004-table" + (a.table == "table1" ? "1" : "2") + ".csv");
  const MethodConfig cfg = LoadMethodConfig(MethodConfigPath("epi"));
  for (const StageConfig& sc : cfg.stages)
    if (sc.name == "epi.enhance") r.enhance = epi::EnhanceOptionsFromParams(sc.params);
  r.plot_png = (fs::path(a.out).parent_path() / (fs::path(a.out).stem().string() + ".png")).string();
  std::ostringstream md;
  EpiWriteIntro(r, md);
  if (a.table == "table1") {
    WriteKeypointTable(r, md);
  } else {
    Matching mt = MeasureMatching(r);
    WriteMatchingTable(r, mt, md);
    WriteDistanceTable(mt, md);
    WritePaperTable2(r.paper, md);
  }
  AtomicWriteFile(a.out, md.str());
  std::cout << "reproduce: wrote " << a.out << "\n";
  return kExitOk;
}

void RegisterEpiTables(TableRegistry& registry) {
  const auto add = [](const std::string& table) {
    return [table](CLI::App& app) {
      auto e = std::make_shared<EpiTableArgs>();
      e->table = table;
      e->out = "reports/epi-" + table + ".md";
      MatrixHelp help;
      help.work = "Working folder for sequences";
      AddMatrixOptions(app, *e, help);
      if (table == "table2") {
        app.add_option("--gap", e->gap, "Frame distance of a matched pair (default 5)");
        app.add_option("--features", e->features, "Features per image (default 500, paper Sec. 4.2)");
      }
      AddReuseCollect(app, *e, "Reuse sequences of an earlier call with identical inputs", "");
      return TableCommand{e, [e] { return RunEpiTable(*e); }};
    };
  };
  registry.Add({"epi-table1", "004 enhanced-epipolar SLAM", "ORB/SIFT keypoints on raw vs enhanced grey, normal and low light",
                "Seed 004 Table 1: ORB/SIFT keypoints per frame on raw vs enhanced (Module A) grey, normal and low light",
                add("table1")});
  registry.Add({"epi-table2", "004 enhanced-epipolar SLAM", "ORB/SIFT x BF/MNN2 matching precision on exact correspondences",
                "Seed 004 Table 2: ORB/SIFT x BF/MNN2 matching precision against exact synthetic correspondences",
                add("table2")});
}

}  // namespace dynref::reproduce
