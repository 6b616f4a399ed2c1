// `dynref run` end to end on the bundled real frames: accuracy, determinism, bad input, and the
// stage hooks (exclusion / weights) reaching the backbone.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/se3.h"
#include "eval/trajectory_eval.h"
#include "io/camera.h"
#include "io/mask_format.h"
#include "io/trajectory.h"
#include "pipeline/pipeline.h"
#include "method/registry.h"
#include "trace/trace_reader.h"
#include "test_support.h"
#include "io/image_file.h"

using namespace dynref;

namespace {

const char* kSeq = "datasets/real/tum_fr1_desk_9frames";

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}


RunOptions Options(const std::string& out, const std::string& trace = "off") {
  RunOptions o;
  o.sequence = test::SourcePath(kSeq);
  o.out_dir = out;
  o.trace_level = trace;
  o.progress = false;
  return o;
}

class ExcludeAllStage : public Stage {
 public:
  std::string name() const override { return "test.exclude_all"; }
  Hook hook() const override { return Hook::kAfterExtraction; }
  void Run(StageContext& ctx) override {
    for (size_t i = 0; i < ctx.frame.view().N(); ++i) ctx.frame.Exclude(static_cast<int>(i), name(), "test");
  }
};

class HalfWeightStage : public Stage {
 public:
  std::string name() const override { return "test.half_weight"; }
  Hook hook() const override { return Hook::kBeforeInitialPose; }
  void Run(StageContext& ctx) override {
    for (size_t i = 0; i < ctx.frame.view().N(); i += 2) ctx.frame.SetWeight(static_cast<int>(i), 0.5);
  }
};

// A registry with the two test stages only (passed to the run: no process-wide registry).
const MethodRegistry& TestRegistry() {
  static const MethodRegistry r = [] {
    MethodRegistry m;
    m.AddStage("test.exclude_all", [](const ParamMap&, SharedState&) { return std::make_unique<ExcludeAllStage>(); });
    m.AddStage("test.half_weight", [](const ParamMap&, SharedState&) { return std::make_unique<HalfWeightStage>(); });
    return m;
  }();
  return r;
}

// The config lives beside the run folder (a run replaces its --out folder as a unit).
std::string WriteConfig(const std::string& run_dir, const std::string& stage) {
  const std::string path = run_dir + ".method.yaml";
  std::ofstream(path) << "method: test\nstages:\n  - name: " << stage << "\n";
  return path;
}

}  // namespace

TEST_CASE("run: real fr1_desk frames, every frame-to-frame motion close to ground truth", "[cli]") {
  const std::string out = test::ScratchDir("run_real");
  const RunResult r = RunSequence(Options(out));
  REQUIRE(r.exit_code == 0);
  CHECK(r.end_state == "complete");
  CHECK(r.frames == 9);
  CHECK(r.tracked == 9);
  const TumTrajectory est = ReadTumTrajectory(out + "/trajectory.txt");
  const TumTrajectory gt = ReadTumTrajectory(test::SourcePath(std::string(kSeq) + "/groundtruth.txt"));
  REQUIRE(est.poses.size() == 9);
  // Every frame-to-frame motion, ground truth (100 Hz) interpolated at the RGB stamps
  // (`dynref eval --rpe-mode interp --delta 1 --delta-unit f`).
  RpeOptions rpe;
  rpe.delta = 1;
  rpe.unit = DeltaUnit::kFrames;
  rpe.mode = RpeMode::kInterp;
  const RpeResult motions = ComputeRpe(gt, est, rpe);
  CHECK(motions.pairs.size() == 8);
  for (const RpePair& p : motions.pairs) {
    const double deg = p.rot_rad * 180.0 / M_PI;
    INFO("motion " << p.est_1);
    WARN("motion " << p.est_1 << ": " << p.trans_m * 1000 << " mm, " << deg << " deg");
    // Regression guard; the issue's target (1 cm / 0.5 deg) is a benchmark reported in the note.
    CHECK(p.trans_m < 0.015);
    CHECK(deg < 1.0);
  }
  const nlohmann::json j = ReadJson(out + "/run.json");
  CHECK(j["method"] == "orb");
  CHECK(j["end_state"] == "complete");
  CHECK(j["tracking_rate"] == 1.0);
  for (const char* module : {"load", "extraction", "tracking", "local_mapping", "ba", "slam", "total"}) {
    CHECK(j["timing"].contains(module));
    CHECK(j["timing"][module]["median_ms_per_frame"].get<double>() >= 0.0);
  }
  CHECK(j["timing"]["total"]["median_ms_per_frame"].get<double>() > 0.0);
  // Means over the first and last min(100, n / 2) frames: with an even number of frames (< 200)
  // the two halves cover the run and average to its mean.
  const nlohmann::json& total = j["timing"]["total"];
  const double frames = j["frames_processed"].get<double>();
  REQUIRE(total["head_tail_frames"].get<double>() == std::floor(frames / 2));
  if (static_cast<int>(frames) % 2 == 0)
    CHECK(0.5 * (total["head_mean_ms_per_frame"].get<double>() + total["tail_mean_ms_per_frame"].get<double>()) ==
          Approx(total["mean_ms_per_frame"].get<double>()));
  CHECK(j["config"]["backbone"]["n_features"]["value"] == "1000");
}

TEST_CASE("run: two runs give byte-identical trajectory and trace dump", "[cli]") {
  const std::string a = test::ScratchDir("run_det_a"), b = test::ScratchDir("run_det_b");
  RunOptions oa = Options(a, "full"), ob = Options(b, "full");
  oa.frames.last = ob.frames.last = 4;
  REQUIRE(RunSequence(oa).exit_code == 0);
  REQUIRE(RunSequence(ob).exit_code == 0);
  REQUIRE(!test::ReadFileBytes(a + "/trajectory.txt").empty());
  REQUIRE(!test::ReadFileBytes(a + "/keyframes.txt").empty());
  CHECK(test::ReadFileBytes(a + "/trajectory.txt") == test::ReadFileBytes(b + "/trajectory.txt"));
  CHECK(test::ReadFileBytes(a + "/keyframes.txt") == test::ReadFileBytes(b + "/keyframes.txt"));
  const auto da = test::RunDynref("trace dump " + a + "/trace.dtr");
  const auto db = test::RunDynref("trace dump " + b + "/trace.dtr");
  REQUIRE(da.exit_code == 0);
  CHECK(da.output.size() > 1000);
  CHECK(da.output == db.output);
}

TEST_CASE("run: --threads 1, 2 and 4 give the same trajectory and trace dump (issue 18)", "[cli]") {
  // orb: ORB levels in parallel; mgd-nd: lines and planes beside ORB as well.
  const std::string method = GENERATE(std::string("orb"), std::string("mgd-nd"));
  std::string dump1, traj1;
  for (int threads : {1, 2, 4}) {
    const std::string out = test::ScratchDir("run_threads_" + method + std::to_string(threads));
    RunOptions o = Options(out, "full");
    o.method = method;
    o.frames.last = 4;
    o.threads = threads;
    REQUIRE(RunSequence(o).exit_code == 0);
    const auto d = test::RunDynref("trace dump " + out + "/trace.dtr");
    REQUIRE(d.exit_code == 0);
    const std::string traj = test::ReadFileBytes(out + "/trajectory.txt");
    if (threads == 1) {
      dump1 = d.output, traj1 = traj;
      REQUIRE(dump1.size() > 1000);
      CHECK(ReadJson(out + "/run.json")["timing_clock"].get<std::string>().rfind("thread CPU time", 0) == 0);
      continue;
    }
    CHECK(d.output == dump1);
    CHECK(traj == traj1);
    CHECK(ReadJson(out + "/run.json")["timing_clock"].get<std::string>().rfind("wall-clock time", 0) == 0);
    CHECK(ReadJson(out + "/run.json")["threads"] == threads);
  }
  RunOptions bad = Options(test::ScratchDir("run_threads_bad"));
  bad.threads = 0;
  CHECK_THROWS_AS(bad.Check(), InputError);
}

TEST_CASE("run: every method end to end gives the same outputs and trace dump for --threads 1, 2 and 4 (issue 18)", "[cli]") {
  // sgdo / epi: Lucas-Kanade slices; mgd: previous-frame matching and diffusion in chunks; epi:
  // enhancement rows; sgdo / semantic: dense back-projection bands (sgdo: also the incremental
  // filter's neighbour statistics); every method: ORB grid rows and descriptor chunks.
  const std::string method = GENERATE(std::string("sgdo"), std::string("mgd"), std::string("blur"),
                                      std::string("epi"), std::string("semantic"));
  const std::string dir = test::ScratchDir("run_threads_" + method);
  REQUIRE(test::RunDynref("synth --preset walking_xyz --frames 6 --seed 1 --detections yolo-like --out " +
                          test::Quote(dir + "/seq")).exit_code == 0);
  std::string dump1;
  for (int threads : {1, 2, 4}) {
    const std::string out = dir + "/run" + std::to_string(threads);
    REQUIRE(test::RunDynref("run --method " + method + " --no-progress --trace full --threads " + std::to_string(threads) +
                            " --sequence " + test::Quote(dir + "/seq") + " --detections " +
                            test::Quote(dir + "/seq/detections/yolo-like") + " --out " + test::Quote(out)).exit_code == 0);
    const auto d = test::RunDynref("trace dump " + test::Quote(out + "/trace.dtr"));
    REQUIRE(d.exit_code == 0);
    if (threads == 1) {
      dump1 = d.output;
      REQUIRE(dump1.size() > 1000);
      continue;
    }
    CHECK(d.output == dump1);
    // Every output file but run.json (timings, thread count) is the same bytes.
    int compared = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(dir + "/run1")) {
      const std::string rel = std::filesystem::relative(entry.path(), dir + "/run1").string();
      if (!entry.is_regular_file() || rel == "run.json") continue;
      INFO(method << " --threads " << threads << ": " << rel);
      CHECK(test::ReadFileBytes(out + "/" + rel) == test::ReadFileBytes(entry.path().string()));
      ++compared;
    }
    CHECK(compared >= 3);
  }
}

TEST_CASE("run: fewer than 2 frames ends cleanly with exit 2 and says why", "[cli]") {
  const std::string out = test::ScratchDir("run_short");
  const auto r = test::RunDynref("run --sequence " + test::SourcePath(kSeq) + " --out " + out + " --frames 0-0");
  CHECK(r.exit_code == 2);
  const nlohmann::json j = ReadJson(out + "/run.json");
  CHECK(j["end_state"].get<std::string>().find("at least 2") != std::string::npos);
  CHECK(std::filesystem::exists(out + "/trajectory.txt"));
  CHECK(std::filesystem::exists(out + "/lost.txt"));
}

TEST_CASE("run: everything masked out is never initialised, every frame listed as lost") {
  const std::string out = test::ScratchDir("run_masked");
  RunOptions o = Options(out, "frames");
  o.registry = &TestRegistry();
  o.config_path = WriteConfig(out, "test.exclude_all");
  o.frames.last = 3;
  const RunResult r = RunSequence(o);
  CHECK(r.exit_code == 2);
  CHECK(r.tracked == 0);
  CHECK(r.end_state.rfind("never-initialised", 0) == 0);
  const std::string lost = test::ReadFileBytes(out + "/lost.txt");
  CHECK(std::count(lost.begin(), lost.end(), '\n') == 5);  // header + 4 frames
  CHECK(ReadJson(out + "/run.json")["frames_all_features_excluded"] == 4);
}

TEST_CASE("run: per-feature weights reach pose optimisation and local BA", "[cli]") {
  const std::string a = test::ScratchDir("run_weight_a"), b = test::ScratchDir("run_weight_b");
  RunOptions oa = Options(a), ob = Options(b, "full");
  ob.registry = &TestRegistry();
  ob.config_path = WriteConfig(b, "test.half_weight");
  REQUIRE(RunSequence(oa).exit_code == 0);
  REQUIRE(RunSequence(ob).exit_code == 0);
  REQUIRE(ReadJson(b + "/run.json")["local_ba_calls"].get<int>() >= 1);  // needs > 2 keyframes
  REQUIRE(!test::ReadFileBytes(a + "/trajectory.txt").empty());
  CHECK(test::ReadFileBytes(a + "/trajectory.txt") != test::ReadFileBytes(b + "/trajectory.txt"));
  // The stage halves every other feature's weight: residuals with weight 0.5 (information =
  // 0.5 x inv_sigma2) must appear in pose optimisation (track.pose#k) and in local BA (localba#k).
  trace::TraceReader reader(b + "/trace.dtr");
  int pose_half = 0, ba_half = 0, pose_total = 0;
  for (size_t g = 0; g < reader.groups().size(); ++g)
    for (const trace::Record& r : reader.ReadGroup(g)) {
      if (r.type != trace::RecordType::kResidual) continue;
      const bool pose = r.stage.rfind("track.pose", 0) == 0;
      const bool ba = r.stage.rfind("localba#", 0) == 0;
      pose_total += pose;
      pose_half += pose && r.weight == 0.5;
      ba_half += ba && r.weight == 0.5;
    }
  CHECK(pose_total > 1000);
  CHECK(pose_half > 300);
  CHECK(ba_half > 300);
}

namespace {

// A copy of the bundled fr1 frames that a test may damage (in scratch dir `name`_seq).
std::string CopyOfRealSequence(const std::string& name) {
  const std::string dir = test::ScratchDir(name + "_seq") + "/seq";
  std::filesystem::copy(test::SourcePath(kSeq), dir, std::filesystem::copy_options::recursive);
  return dir;
}

std::vector<std::string> ListedImages(const std::string& list_file) {
  std::vector<std::string> paths;
  std::ifstream in(list_file);
  std::string stamp, path;
  while (in >> stamp) {
    if (stamp[0] == '#') {
      std::getline(in, path);
      continue;
    }
    in >> path;
    paths.push_back(path);
  }
  return paths;
}

}  // namespace

TEST_CASE("run: an unreadable frame mid-sequence ends the run cleanly, naming the file", "[cli]") {
  const std::string seq = CopyOfRealSequence("run_unreadable");
  const std::vector<std::string> rgb = ListedImages(seq + "/rgb.txt");
  REQUIRE(rgb.size() == 9);
  test::WriteText(seq + "/" + rgb[5], "not a png");
  const std::string out = test::ScratchDir("run_unreadable") + "/run";
  REQUIRE(std::filesystem::exists(seq + "/rgb.txt"));
  const auto r = test::RunDynref("run --camera tum_fr1 --sequence " + test::Quote(seq) + " --out " +
                                 test::Quote(out));
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("rgb.txt") != std::string::npos);  // list file and line of the frame
  CHECK(r.output.find(rgb[5]) != std::string::npos);
  const nlohmann::json j = ReadJson(out + "/run.json");
  CHECK(j["end_state"].get<std::string>().rfind("error: frame 5", 0) == 0);
  CHECK(j["frames_processed"] == 5);
  // What was written is complete up to the bad frame: frames 0-4 have poses.
  CHECK(ReadTumTrajectory(out + "/trajectory.txt").poses.size() == 5);
  CHECK(std::system(("ls " + test::Quote(out) + " | grep -q tmp").c_str()) != 0);
}

TEST_CASE("run: zero depth in every frame is never initialised, one zero-depth frame is survived") {
  const std::string seq = CopyOfRealSequence("run_zero_depth");
  const std::vector<std::string> depth = ListedImages(seq + "/depth.txt");
  REQUIRE(depth.size() == 9);
  const cv::Mat zero(480, 640, CV_16UC1, cv::Scalar(0));
  REQUIRE(dynref::ImageWrite(seq + "/" + depth[4], zero));
  RunOptions o = Options(test::ScratchDir("run_zero_depth") + "/one");
  o.sequence = seq;
  o.camera = "tum_fr1";
  REQUIRE(std::filesystem::exists(seq + "/depth.txt"));
  const RunResult one = RunSequence(o);
  CHECK(one.exit_code == 0);
  CHECK(one.frames == 9);
  CHECK(one.tracked + one.lost == 9);  // every frame has a pose or a line in lost.txt
  CHECK(ReadJson(o.out_dir + "/run.json")["frames_zero_depth"] == 1);

  for (const std::string& d : depth) REQUIRE(dynref::ImageWrite(seq + "/" + d, zero));
  o.out_dir = test::ScratchDir("run_zero_depth") + "/all";
  const RunResult all = RunSequence(o);
  CHECK(all.exit_code == 2);
  CHECK(all.tracked == 0);
  CHECK(all.end_state == "never-initialised: depth is zero in every frame");
  const std::string lost = test::ReadFileBytes(o.out_dir + "/lost.txt");
  CHECK(std::count(lost.begin(), lost.end(), '\n') == 10);  // header + 9 frames
}

TEST_CASE("run: a detection mask of the wrong size mid-run ends the run cleanly, naming the PNG", "[cli]") {
  const std::string dir = test::ScratchDir("run_bad_mask");
  const auto s = test::RunDynref("synth --preset walking_xyz --frames 4 --seed 1 --detections ideal --out " +
                                 test::Quote(dir + "/seq"));
  REQUIRE(s.exit_code == 0);
  const std::string det = dir + "/seq/detections/ideal";
  std::vector<std::string> pngs;
  for (const auto& entry : std::filesystem::directory_iterator(det))
    if (entry.path().extension() == ".png") pngs.push_back(entry.path().string());
  std::sort(pngs.begin(), pngs.end());
  REQUIRE(pngs.size() == 4);
  REQUIRE(dynref::ImageWrite(pngs[2], cv::Mat(240, 320, CV_16UC1, cv::Scalar(0))));
  const std::string out = dir + "/run";
  const auto r = test::RunDynref("run --method sgdo --no-progress --sequence " + test::Quote(dir + "/seq") +
                                 " --detections " + test::Quote(det) + " --out " + test::Quote(out));
  CHECK(r.exit_code == 2);
  CHECK(r.output.find(pngs[2] + ": instance-id PNG is 320x240, the images are 640x480") != std::string::npos);
  const nlohmann::json j = ReadJson(out + "/run.json");
  CHECK(j["end_state"].get<std::string>().rfind("error: frame 2", 0) == 0);
  CHECK(j["frames_processed"] == 2);
  CHECK(ReadTumTrajectory(out + "/trajectory.txt").poses.size() == 2);
  // The reader itself: size check only when the image size is given; a repeated instance id
  // is rejected naming the record file.
  const DetectionsReader reader(det);
  const std::vector<std::string> stamps = reader.Stamps();
  REQUIRE(stamps.size() == 4);
  CHECK_NOTHROW(reader.Read(stamps[2]));
  CHECK_THROWS_AS(reader.Read(stamps[2], cv::Size(640, 480)), InputError);
  const std::string txt = pngs[1].substr(0, pngs[1].size() - 4) + ".txt";
  std::string records = test::ReadFileBytes(txt);
  const size_t first_record = records.find_first_of("0123456789");
  REQUIRE(first_record != std::string::npos);
  records += records.substr(first_record, records.find('\n', first_record) + 1 - first_record);
  test::WriteText(txt, records);
  CHECK_THROWS_WITH(reader.Read(stamps[1]), Catch::Matchers::Contains(txt) &&
                                                Catch::Matchers::Contains("appears twice"));
}

TEST_CASE("run: a rerun into the same folder removes the earlier run's trace and overlays") {
  const std::string out = test::ScratchDir("run_rerun");
  RunOptions o = Options(out, "full");
  o.frames.last = 2;
  o.overlays = true;
  REQUIRE(RunSequence(o).exit_code == 0);
  REQUIRE(std::filesystem::exists(out + "/trace.dtr"));
  REQUIRE(std::filesystem::exists(out + "/overlays"));
  o.trace_level = "off";
  o.overlays = false;
  REQUIRE(RunSequence(o).exit_code == 0);
  CHECK(std::filesystem::exists(out + "/run.json"));
  CHECK(!std::filesystem::exists(out + "/trace.dtr"));
  CHECK(!std::filesystem::exists(out + "/overlays"));
  // Overlays are drawn from a full trace: asking with a lighter trace fails before running.
  o.trace_level = "frames";
  o.overlays = true;
  CHECK_THROWS_WITH(RunSequence(o), Catch::Matchers::Contains("--overlays needs --trace full"));
}

TEST_CASE("run: a camera too small for ORB extraction is named before any work (issue 20 item 10)", "[cli]") {
  // A consistent 1 x 1 sequence (the image-size check against the camera passes): before, the
  // ORB extractor ended in a raw OpenCV assertion.
  const std::string dir = test::ScratchDir("run_tiny_camera");
  const std::string seq = dir + "/seq";
  std::filesystem::create_directories(seq + "/rgb");
  std::filesystem::create_directories(seq + "/depth");
  std::string rgb_txt = "# color images\n", depth_txt = "# depth images\n";
  for (int i = 0; i < 3; ++i) {
    const std::string t = std::to_string(100 + i) + ".000000";
    REQUIRE(dynref::ImageWrite(seq + "/rgb/" + t + ".png", cv::Mat(1, 1, CV_8UC3, cv::Scalar(50, 60, 70))));
    REQUIRE(dynref::ImageWrite(seq + "/depth/" + t + ".png", cv::Mat(1, 1, CV_16U, cv::Scalar(5000))));
    rgb_txt += t + " rgb/" + t + ".png\n";
    depth_txt += t + " depth/" + t + ".png\n";
  }
  test::WriteText(seq + "/rgb.txt", rgb_txt);
  test::WriteText(seq + "/depth.txt", depth_txt);
  Camera tiny = CameraPreset("tum_fr3");
  tiny.width = 1, tiny.height = 1, tiny.cx = 0, tiny.cy = 0;  // the principal point must lie inside
  WriteOrbSlamCameraYaml(tiny, seq + "/camera.yaml");
  const auto r = test::RunDynref("run --sequence " + test::Quote(seq) + " --out " + test::Quote(dir + "/run"));
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("is too small for ORB extraction") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir + "/run"));
}
