#include "fuzz_targets.h"

#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "detect/label_png_import.h"
#include "io/camera.h"
#include "io/mask_format.h"
#include "io/sequence.h"
#include "io/stamped_list.h"
#include "io/trajectory.h"
#include "pipeline/method_config.h"
#include "trace/trace_reader.h"
#include "trace/trace_writer.h"
#include "io/image_file.h"

namespace dynref::fuzz {
namespace fs = std::filesystem;
namespace {

std::string Slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("fuzz: cannot read seed " + path);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}
void WriteBytesTo(const std::string& path, const std::string& bytes) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream f(path, std::ios::binary);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}
std::string Source(const std::string& rel) { return std::string(DYNREF_SOURCE_DIR) + "/" + rel; }
// First `n` lines of a file in the source tree.
std::string Head(const std::string& rel, int n) {
  std::ifstream f(Source(rel));
  std::string out, line;
  for (int i = 0; i < n && std::getline(f, line); ++i) out += line + "\n";
  return out;
}

constexpr int kW = 64, kH = 48;  // tiny frames keep an execution in the tens of microseconds

Camera TinyCamera() {
  Camera c = CameraPreset("synthetic");
  c.name = "fuzz";
  c.width = kW, c.height = kH;
  c.fx = c.fy = 50, c.cx = 32, c.cy = 24;
  c.k1 = 0.01;
  return c;
}

std::vector<Seed> SetupSequence(const std::string& work) {
  fs::create_directories(work + "/rgb");
  fs::create_directories(work + "/depth");
  std::string rgb = "# color images\n", depth = "# depth maps\n", gt = "# ground truth\n";
  for (int i = 0; i < 3; ++i) {
    const std::string stamp = "1305031102." + std::to_string(100 + 33 * i);
    dynref::ImageWrite(work + "/rgb/" + stamp + ".png", cv::Mat(kH, kW, CV_8UC3, cv::Scalar(10 * i, 50, 90)));
    dynref::ImageWrite(work + "/depth/" + stamp + ".png", cv::Mat(kH, kW, CV_16U, cv::Scalar(5000 + i)));
    rgb += stamp + " rgb/" + stamp + ".png\n";
    depth += stamp + " depth/" + stamp + ".png\n";
    gt += stamp + " 0." + std::to_string(i) + " 0 1 0 0 0 1\n";
  }
  WriteOrbSlamCameraYaml(TinyCamera(), work + "/camera.yaml");
  std::vector<Seed> seeds = {{"rgb.txt", rgb}, {"depth.txt", depth}, {"groundtruth.txt", gt},
                             {"camera.yaml", Slurp(work + "/camera.yaml")}};
  for (const Seed& s : seeds) WriteBytesTo(work + "/" + s.file, s.bytes);
  seeds.push_back({"rgb/1305031102.100.png", Slurp(work + "/rgb/1305031102.100.png")});
  seeds.push_back({"depth/1305031102.100.png", Slurp(work + "/depth/1305031102.100.png")});
  return seeds;
}

void RunSequence(const std::string& work) {
  const Sequence seq = OpenSequence(work);
  for (const FrameEntry& f : seq.frames) {
    LoadRgb(seq, f);
    LoadDepthMeters(seq, f);
  }
}

std::vector<Seed> SetupMaskFormat(const std::string& work) {
  {
    DetectionsWriter w(work, "fuzz", "-");
    FrameDetections a;
    a.stamp_text = "1305031102.100";
    a.instance_ids = cv::Mat(kH, kW, CV_16U, cv::Scalar(0));
    a.instance_ids(cv::Rect(4, 4, 10, 20)).setTo(1);
    a.instance_ids(cv::Rect(30, 10, 12, 12)).setTo(3);
    a.instances = {{1, 0, "person", 0.9, 4, 4, 13, 23, true},
                   {2, 56, "chair", 0.4, 20, 20, 40, 40, false},
                   {3, 0, "person", 0.7, 30, 10, 41, 21, true}};
    w.Write(a);
    FrameDetections b;
    b.stamp_text = "1305031102.133";
    b.instances = {{1, 2, "car", 0.55, 0, 0, 63, 47, false}};
    w.Write(b);
    w.Finish();
  }
  std::vector<Seed> seeds;
  for (const char* f : {"format.txt", "index.txt", "1305031102.100.txt", "1305031102.133.txt",
                        "1305031102.100.png"})
    seeds.push_back({f, Slurp(work + "/" + f)});
  return seeds;
}

void RunMaskFormat(const std::string& work) {
  DetectionsReader r(work);
  for (const std::string& stamp : r.Stamps()) {
    const FrameDetections d = r.Read(stamp, cv::Size(kW, kH));
    for (const DetectedInstance& i : d.instances) d.MaskOf(i.id);
  }
}

std::vector<Seed> SetupLabels(const std::string& work) {
  const std::string yaml =
      "png_kind: instance\nconfidence: 0.8\nmin_area_px: 2\nlabels: {1: person, 2: chair, 7: dog}\n";
  cv::Mat png(kH, kW, CV_8U, cv::Scalar(0));
  png(cv::Rect(2, 2, 10, 10)).setTo(1);
  png(cv::Rect(20, 5, 8, 30)).setTo(2);
  png(cv::Rect(40, 30, 3, 3)).setTo(7);
  WriteBytesTo(work + "/labels.yaml", yaml);
  dynref::ImageWrite(work + "/1305031102.100.png", png);
  return {{"labels.yaml", yaml},
          {"labels.yaml", "png_kind: semantic\nlabels:\n  1: person\n  2: chair\n  7: dog\n"},
          {"1305031102.100.png", Slurp(work + "/1305031102.100.png")}};
}

void RunLabels(const std::string& work) {
  const detect::LabelTable t = detect::ReadLabelTable(work + "/labels.yaml");
  detect::ReadLabelPng(t, work + "/1305031102.100.png", "1305031102.100");
}

std::vector<Seed> SetupTrace(const std::string& work) {
  using namespace trace;
  RunHeader h;
  h.dynref_version = "0.1.0";
  h.dynref_commit = "fuzz";
  h.method = "fuzz";
  h.config_json = "{\"a\":1}";
  {
    TraceWriter w(work + "/v2.dtr", Level::kFull, h);
    w.ProbabilityUpdate("setup", EntityKind::kFrame, "x", {}, 0, 0);
    for (int f = 0; f < 3; ++f) {
      w.BeginFrame(f, 0.5 * f);
      w.FramePose("final", SE3::Identity());
      w.FrameCount("extract", "keypoints", 10 + f);
      w.Observation(0, f - 1, 1.5, 2.5, 0.5, 1, 0xABCDEFull);
      w.ProbabilityUpdate("mgd.fuse", EntityKind::kMapPoint, "mp1", {{"a", 1}, {"b", 2}}, 0.2, 0.4);
      w.Residual("track.pose#1", "rgbd3", "mp1@f0", {1, 2, 3}, {0.1, 0.2, 0.3}, 1, 1, 0.5, 0.2, true);
      w.Decision("sgdo.depth", EntityKind::kFeature, "f0.0", f % 2, "ok");
    }
    w.Close("complete");
  }
  // Schema 1 has no checksums, so its mutations reach the record decoder.
  return {{"trace.dtr", Slurp(work + "/v2.dtr")},
          {"trace.dtr", Slurp(Source("tests/data/trace_v1/orb_30f_schema1.dtr"))}};
}

void RunTrace(const std::string& work) {
  trace::TraceReader r(work + "/trace.dtr");
  for (size_t g = 0; g < r.groups().size(); ++g) trace::FlattenGroup(r.ReadGroup(g));
}

std::vector<Seed> FileSeeds(const std::string& file, const std::vector<std::string>& contents) {
  std::vector<Seed> out;
  for (const std::string& c : contents) out.push_back({file, c});
  return out;
}

}  // namespace

std::vector<Target> AllTargets() {
  std::vector<Target> t;
  t.push_back({"stamped-list", "ReadStampedList (rgb.txt, depth.txt, associations)",
               [](const std::string&) {
                 return FileSeeds("list.txt",
                                  {Head("datasets/real/tum_fr1_desk_9frames/rgb.txt", 12),
                                   Head("datasets/real/tum_fr1_desk_9frames/depth.txt", 12),
                                   "1.0 a b\n1.5\tc d\n2,e,f\n"});
               },
               [](const std::string& w) {
                 ReadStampedList(w + "/list.txt", 1, 1);
                 ReadStampedList(w + "/list.txt", 1, -1, true);
               }});
  t.push_back({"trajectory", "ReadTumTrajectory (ground truth and estimates)",
               [](const std::string&) {
                 return FileSeeds("traj.txt",
                                  {Head("datasets/real/trajectories/fr2_desk_groundtruth.txt", 20),
                                   Head("datasets/real/trajectories/fr2_desk_ORB.txt", 20),
                                   Head("datasets/real/tum_fr1_desk_9frames/groundtruth.txt", 20)});
               },
               [](const std::string& w) {
                 for (DuplicateStamps d : {DuplicateStamps::kKeepLast, DuplicateStamps::kKeepAll})
                   ReadTumTrajectory(w + "/traj.txt", {d, true, 1e-3});
               }});
  t.push_back({"sequence", "OpenSequence + LoadRgb/LoadDepthMeters (TUM/Bonn folders)",
               SetupSequence, RunSequence});
  t.push_back({"camera-yaml", "ReadOrbSlamCameraYaml",
               [](const std::string& w) {
                 WriteOrbSlamCameraYaml(TinyCamera(), w + "/camera.yaml");
                 WriteOrbSlamCameraYaml(CameraPreset("tum_fr1"), w + "/fr1.yaml");
                 return FileSeeds("camera.yaml", {Slurp(w + "/camera.yaml"), Slurp(w + "/fr1.yaml")});
               },
               [](const std::string& w) { ReadOrbSlamCameraYaml(w + "/camera.yaml"); }});
  t.push_back({"method-yaml", "LoadMethodConfig (configs/*.yaml)",
               [](const std::string&) {
                 std::vector<std::string> texts;
                 for (const char* m : {"orb", "sgdo", "mgd", "semantic", "sgdo_vote"})
                   texts.push_back(Slurp(Source(std::string("configs/") + m + ".yaml")));
                 return FileSeeds("method.yaml", texts);
               },
               [](const std::string& w) { LoadMethodConfig(w + "/method.yaml").ToJson(); }});
  t.push_back({"mask-format", "DetectionsReader + Read + MaskOf (datasets/MASK_FORMAT.md)",
               SetupMaskFormat, RunMaskFormat});
  t.push_back({"label-import", "ReadLabelTable + ReadLabelPng (dynref detect --source labels:)",
               SetupLabels, RunLabels});
  t.push_back({"trace", "TraceReader + ReadGroup + FlattenGroup (schema 1 and 2)", SetupTrace,
               RunTrace});
  return t;
}

}  // namespace dynref::fuzz
