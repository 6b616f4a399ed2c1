#include "synth/synth.h"

#include "synth/scene_export.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <sys/stat.h>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "core/rng.h"
#include "core/version.h"
#include "io/camera.h"
#include "io/mask_format.h"
#include "synth/degrade.h"
#include "synth/sensor.h"
#include "synth/world.h"
#include "io/image_file.h"

namespace dynref::synth {
namespace {

void WritePng(const std::string& path, const cv::Mat& image) {
  const std::string tmp = TempPathFor(path) + ".png";
  if (!dynref::ImageWrite(tmp, image)) throw std::runtime_error("cannot write " + tmp);
  AtomicRename(tmp, path);
}

// An item moves in this frame if any corner of its mesh bounds moved > 1 mm since t - 1/30 s.
constexpr double kMovingThresholdM = 0.001;
bool ItemMoves(const DrawItem& now, const DrawItem& before) {
  Eigen::Vector3f lo, hi;
  now.mesh->Bounds(&lo, &hi);
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d p((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(), (c & 4) ? hi.z() : lo.z());
    if ((now.T_wo * p - before.T_wo * p).norm() > kMovingThresholdM) return true;
  }
  return false;
}

std::string Stamp(double s) { return FormatFixed(s, 6); }

std::string PoseLine(const std::string& stamp, const SE3& T_wc) {
  const Eigen::Quaterniond q(T_wc.linear());
  const Eigen::Vector3d t = T_wc.translation();
  std::ostringstream o;
  o << stamp << ' ' << FormatFixed(t.x(), 6) << ' ' << FormatFixed(t.y(), 6) << ' ' << FormatFixed(t.z(), 6) << ' '
    << FormatFixed(q.x(), 6) << ' ' << FormatFixed(q.y(), 6) << ' ' << FormatFixed(q.z(), 6) << ' '
    << FormatFixed(q.w(), 6) << '\n';
  return o.str();
}

std::string LabelsYaml(const Scene& scene) {
  std::ostringstream o;
  o << "# dynref synth ground-truth labels: instance id -> class (COCO id, -1 = not a COCO class)\n"
    << "instances:\n";
  for (const auto& [id, l] : scene.labels)
    o << "  " << id << ": {class_name: " << l.class_name << ", coco_id: " << l.coco_id
      << ", prior_dynamic: " << (l.prior_dynamic ? "true" : "false") << "}\n";
  return o.str();
}

namespace fs = std::filesystem;

// A folder written by dynref synth: its synth.yaml names the generator (written by
// GenerateSequence below). Like `dynref reproduce`, we only ever replace what we wrote ourselves.
bool IsSynthOutput(const fs::path& dir) {
  std::ifstream in(dir / "synth.yaml");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("generator: dynref", 0) == 0) return true;
  return false;
}

// InputError (naming the --out folder as given) unless the target is absent, an empty folder or
// a previous dynref synth output.
void CheckReplaceable(const fs::path& target, const std::string& shown) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(target, ec);
  if (ec || !fs::exists(st)) return;
  if (!fs::is_directory(fs::status(target, ec)))
    throw InputError(shown, "exists and is not a directory; refusing to overwrite");
  if (fs::is_empty(target, ec) && !ec) return;
  if (!IsSynthOutput(target))
    throw InputError(shown, "exists and was not written by dynref synth (no synth.yaml naming the generator); "
                            "refusing to overwrite");
}

// The camera for --width W (0 = unchanged): every pixel quantity scaled by W / width, pixel
// centres kept (cx' = (cx + 0.5) s - 0.5); bf = baseline * fx scales with fx, ThDepth (baselines) not.
Camera ScaledCamera(Camera c, int width) {
  if (width == 0 || width == c.width) return c;
  const double s = double(width) / c.width;
  c.fx *= s, c.fy *= s, c.bf *= s;
  c.cx = (c.cx + 0.5) * s - 0.5, c.cy = (c.cy + 0.5) * s - 0.5;
  c.height = c.height * width / c.width;
  c.width = width;
  return c;
}

bool IsReplaceableSynthTarget(const std::string& dir) {
  std::error_code ec;
  return IsAbsentOrEmptyDirectory(dir) || (fs::is_directory(dir, ec) && IsSynthOutput(dir));
}

}  // namespace

void SynthOptions::Check() const {
  GetPreset(preset);  // throws for an unknown preset
  if (frames < 0) throw InputError("--frames", "must be >= 0 (0 = preset default)");
  if (frames > kMaxFrames)
    throw InputError("--frames", "must be <= " + std::to_string(kMaxFrames) + " (got " + std::to_string(frames) + ")");
  if (width != 0 && (width < kMinWidth || width > 640 || width % 4 != 0))
    throw InputError("--width", "must be 0 (640) or a multiple of 4 in " + std::to_string(kMinWidth) +
                                    "..640 (got " + std::to_string(width) + ")");
  if (out.empty()) throw InputError("--out", "output directory required");
  if (detections != "none" && detections != "all") ProfileFor(detections);
  if (blur_subframes < 2) throw InputError("blur_subframes", "must be >= 2");
  if (!(exposure_s > 0 && exposure_s <= 0.1)) throw InputError("exposure_s", "must be in (0, 0.1]");
}

namespace {

// Creates the sequence's folders (inside the staging folder); returns out.
std::string SeqEnsureDirectories(const std::string& out) {
  EnsureDirectory(out);
  EnsureDirectory(out + "/rgb");
  EnsureDirectory(out + "/depth");
  EnsureDirectory(out + "/gt");
  EnsureDirectory(out + "/gt/motion");
  return out;
}

// The output of one sequence: per-frame writers and the text lists built up frame by frame.
struct SeqFiles {
  SeqFiles(const std::string& staging_dir, const SynthOptions& opt, const World& world)
      : out(SeqEnsureDirectories(staging_dir)), gt_writer(out + "/gt", "gt", "") {
    if (opt.detections == "all") modes = {"ideal", "yolo-like", "sparseinst-like"};
    else if (opt.detections != "none") modes = {opt.detections};
    if (!modes.empty()) EnsureDirectory(out + "/detections");
    for (const auto& m : modes) {
      det_writers.push_back(std::make_unique<DetectionsWriter>(out + "/detections/" + m, "synthetic:" + m, ""));
      degraders.emplace_back(ProfileFor(m), world.scene().labels, opt.seed, opt.blur ? opt.exposure_s * kFrameRateHz : 0.0);
    }
    dropped_txt = std::vector<std::ostringstream>(modes.size());
    for (size_t m = 0; m < modes.size(); ++m)
      dropped_txt[m] << "# what the " << modes[m] << " degradation did to GT instances (datasets/README.md)\n"
                     << "# rgb_stamp gt_id:what:blur_px[:shrink_px] ... (what = missed | small-missed | shrunk | overpainted)\n";
    const std::string header = "# dynref synth " + opt.preset + " seed " + std::to_string(opt.seed) + "\n";
    rgb_txt << "# color images\n" << header << "# timestamp filename\n";
    depth_txt << "# depth maps\n" << header << "# timestamp filename\n";
    gt_txt << "# ground truth trajectory (T_wc, camera to world)\n" << header << "# timestamp tx ty tz qx qy qz qw\n";
    moving_txt << "# rgb_stamp ids of instances that move in this frame (> 1 mm since the previous frame)\n";
  }
  std::string out;
  DetectionsWriter gt_writer;
  std::vector<std::string> modes;
  std::vector<std::unique_ptr<DetectionsWriter>> det_writers;
  std::vector<Degrader> degraders;
  std::vector<std::ostringstream> dropped_txt;
  std::ostringstream rgb_txt, depth_txt, gt_txt, assoc_txt, moving_txt;
};

// Render buffers reused from frame to frame.
struct SeqBuffers {
  std::vector<DrawItem> items, items_prev, sub_items;
  GBuffer gb, sub_gb;
  cv::Mat radiance, sub_radiance, sum;
};

// Renders the frame at time t into b->gb and b->radiance.
void SeqRenderFrame(const World& world, const Intrinsics& K, const SynthOptions& opt, double t, const SE3& T_wc,
                    SeqBuffers* b) {
  world.Items(t, &b->items);
  Rasterize(K, T_wc.inverse(), b->items, &b->gb);
  if (!opt.blur) ShadeRadiance(world.scene(), K, T_wc, b->gb, &b->radiance);
  else {  // seed 003: blur = average of sub-frame renders over the exposure
    b->sum = cv::Mat::zeros(K.height, K.width, CV_32FC3);
    for (int k = 0; k < opt.blur_subframes; ++k) {
      const double tk = t + opt.exposure_s * ((k + 0.5) / opt.blur_subframes - 0.5);
      const SE3 T_wc_k = world.CameraT_wc(tk);
      world.Items(tk, &b->sub_items);
      Rasterize(K, T_wc_k.inverse(), b->sub_items, &b->sub_gb);
      ShadeRadiance(world.scene(), K, T_wc_k, b->sub_gb, &b->sub_radiance);
      b->sum += b->sub_radiance;
    }
    b->radiance = b->sum / double(opt.blur_subframes);
  }
}

// Ground truth of the rendered frame: instance ids, body parts, depth, the motion mask, and which
// draw items / instances move since the previous frame.
void SeqGroundTruth(const World& world, const Intrinsics& K, double t, SeqBuffers* b, std::vector<uint8_t>* moving,
                    std::set<int>* moving_ids, GtFrame* gt, cv::Mat* motion) {
  world.Items(t - 1.0 / kFrameRateHz, &b->items_prev);
  moving->assign(b->items.size(), 0);
  for (size_t k = 1; k < b->items.size(); ++k)
    if (ItemMoves(b->items[k], b->items_prev[k])) {
      (*moving)[k] = 1;
      moving_ids->insert(world.ItemInstance(k));
    }
  gt->instance_ids.create(K.height, K.width, CV_16U);
  gt->body_part.create(K.height, K.width, CV_8S);
  gt->depth_m.create(K.height, K.width, CV_32F);
  motion->create(K.height, K.width, CV_8U);
  const GBuffer& gb = b->gb;
  for (int y = 0; y < K.height; ++y)
    for (int x = 0; x < K.width; ++x) {
      const size_t idx = size_t(y) * K.width + x;
      const int32_t f = gb.face[idx];
      const FaceRecord* rec = f >= 0 ? &gb.faces[size_t(f)] : nullptr;
      gt->instance_ids.at<uint16_t>(y, x) = rec ? rec->instance : 0;
      gt->body_part.at<int8_t>(y, x) = int8_t(rec ? world.ItemBodyPart(size_t(rec->part)) : -1);
      gt->depth_m.at<float>(y, x) = rec ? gb.z[idx] : 0.f;
      motion->at<uint8_t>(y, x) = rec && (*moving)[size_t(rec->part)] ? 255 : 0;
    }
}

// Writes frame i's images and detections and appends its lines to the lists.
void SeqWriteFrame(const World& world, int i, const std::string& rgb_stamp, const std::string& depth_stamp,
                   const SE3& T_wc, const cv::Mat& rgb, const cv::Mat& depth, const GtFrame& gt, const cv::Mat& motion,
                   const std::set<int>& moving_ids, SeqFiles* files) {
  const std::string& out = files->out;
  WritePng(out + "/rgb/" + rgb_stamp + ".png", rgb);
  WritePng(out + "/depth/" + depth_stamp + ".png", depth);
  files->gt_writer.Write(GtDetections(gt, world.scene().labels));
  WritePng(out + "/gt/motion/" + rgb_stamp + ".png", motion);
  for (size_t m = 0; m < files->modes.size(); ++m) {
    files->det_writers[m]->Write(files->degraders[m].Apply(i, gt));
    files->dropped_txt[m] << DegradeEventsLine(rgb_stamp, files->degraders[m].events());
  }
  files->rgb_txt << rgb_stamp << " rgb/" << rgb_stamp << ".png\n";
  files->depth_txt << depth_stamp << " depth/" << depth_stamp << ".png\n";
  files->assoc_txt << rgb_stamp << " rgb/" << rgb_stamp << ".png " << depth_stamp << " depth/" << depth_stamp << ".png\n";
  files->gt_txt << PoseLine(rgb_stamp, T_wc);
  files->moving_txt << rgb_stamp;
  for (int id : moving_ids) files->moving_txt << ' ' << id;
  files->moving_txt << '\n';
}

// camera.yaml and synth.yaml (the parameters that reproduce the sequence).
void SeqWriteMetadata(const SynthOptions& opt, const Camera& camera, int n, const std::string& out) {
  WriteOrbSlamCameraYaml(camera, out + "/camera.yaml");
  std::ostringstream meta;
  // --width appears only when given, so a full-size sequence's synth.yaml is unchanged.
  const std::string width_arg = opt.width ? " --width " + std::to_string(opt.width) : "";
  meta << "# dynref synth parameters (reproduce with: dynref synth --preset " << opt.preset << " --frames " << n
       << " --seed " << opt.seed << (opt.blur ? " --blur" : "") << (opt.low_light ? " --low-light" : "")
       << " --detections " << opt.detections << width_arg << ")\n"
       << "generator: dynref " << DYNREF_VERSION << "\npreset: " << opt.preset << "\nframes: " << n
       << "\nseed: " << opt.seed << "\nblur: " << (opt.blur ? "true" : "false")
       << "\nlow_light: " << (opt.low_light ? "true" : "false") << "\ndetections: " << opt.detections
       << "\nblur_subframes: " << opt.blur_subframes << "\nexposure_s: " << FormatDouble17(opt.exposure_s) << "\n";
  if (opt.width) meta << "width: " << camera.width << "\nheight: " << camera.height << "\n";
  AtomicWriteFile(out + "/synth.yaml", meta.str());
}

// Ground-truth side files, then the lists that make the folder readable (last).
void SeqFinishFiles(const World& world, SceneGeometryRecorder& geometry, SeqFiles* files) {
  const std::string& out = files->out;
  AtomicWriteFile(out + "/gt/labels.yaml", LabelsYaml(world.scene()));
  AtomicWriteFile(out + "/gt/moving.txt", files->moving_txt.str());
  geometry.Write(out + "/gt");
  for (size_t m = 0; m < files->modes.size(); ++m)
    AtomicWriteFile(out + "/gt/dropped-" + files->modes[m] + ".txt", files->dropped_txt[m].str());
  files->gt_writer.Finish();
  for (auto& w : files->det_writers) w->Finish();
  AtomicWriteFile(out + "/depth.txt", files->depth_txt.str());
  AtomicWriteFile(out + "/groundtruth.txt", files->gt_txt.str());
  AtomicWriteFile(out + "/associations.txt", files->assoc_txt.str());
  AtomicWriteFile(out + "/rgb.txt", files->rgb_txt.str());
}

Intrinsics SeqIntrinsics(const Camera& camera) {
  Intrinsics K;
  K.width = camera.width, K.height = camera.height;
  K.fx = float(camera.fx), K.fy = float(camera.fy), K.cx = float(camera.cx), K.cy = float(camera.cy);
  return K;
}

}  // namespace

SynthStats GenerateSequence(const SynthOptions& opt) {
  opt.Check();
  using Clock = std::chrono::steady_clock;
  const auto t_start = Clock::now();
  const std::clock_t cpu_start = std::clock();
  double render_ms = 0, render_cpu_ms = 0;
  const World world(GetPreset(opt.preset), opt.seed);
  const int n = opt.frames > 0 ? opt.frames : world.preset().default_frames;
  const Camera camera = ScaledCamera(CameraPreset("synthetic"), opt.width);
  const Intrinsics K = SeqIntrinsics(camera);
  const SensorModel sensor;

  // The sequence is built in a sibling temp folder and renamed onto --out only when complete, so a
  // failed or killed run never leaves a partial sequence (or stale frames of an earlier run) there.
  const fs::path target = StagingDirectory::NormalisedTarget(opt.out);
  CheckReplaceable(target, opt.out);  // refuse before rendering anything
  StagingDirectory staging(target.string());
  SeqFiles files(staging.dir(), opt, world);

  SceneGeometryRecorder geometry(world);
  Rng timing(opt.seed, "synth.timing");
  SeqBuffers b;
  for (int i = 0; i < n; ++i) {
    // Kinect-like log: rgb at 30 Hz with +-0.3 ms jitter, depth 0.5..3 ms later (TUM associate.py
    // pairs them; max_difference 0.02 s).
    const double t = double(i) / kFrameRateHz + timing.Uniform(-0.0003, 0.0003);
    const double depth_dt = timing.Uniform(0.0005, 0.003);
    const std::string rgb_stamp = Stamp(kStampBase + t), depth_stamp = Stamp(kStampBase + t + depth_dt);
    const auto t_frame = Clock::now();
    const std::clock_t cpu_frame = std::clock();
    const SE3 T_wc = world.CameraT_wc(t);
    SeqRenderFrame(world, K, opt, t, T_wc, &b);
    Rng rgb_rng(opt.seed, "synth.rgb." + std::to_string(i)), depth_rng(opt.seed, "synth.depth." + std::to_string(i));
    const cv::Mat rgb = SenseRgb(sensor, b.radiance, opt.low_light, rgb_rng);
    const cv::Mat depth = SenseDepth(sensor, b.gb, depth_rng);
    render_ms += std::chrono::duration<double, std::milli>(Clock::now() - t_frame).count();
    render_cpu_ms += 1000.0 * double(std::clock() - cpu_frame) / CLOCKS_PER_SEC;

    std::vector<uint8_t> moving;
    std::set<int> moving_ids;
    GtFrame gt;
    gt.stamp_text = rgb_stamp;
    cv::Mat motion;
    SeqGroundTruth(world, K, t, &b, &moving, &moving_ids, &gt, &motion);
    geometry.AddFrame(b.items, moving, moving_ids, gt.instance_ids, gt.depth_m, K, T_wc);
    SeqWriteFrame(world, i, rgb_stamp, depth_stamp, T_wc, rgb, depth, gt, motion, moving_ids, &files);
  }
  // Metadata first, the lists that make the folder readable last.
  SeqWriteMetadata(opt, camera, n, files.out);
  SeqFinishFiles(world, geometry, &files);
  PublishDirectory(staging.dir(), target.string(), opt.out, IsReplaceableSynthTarget,
                   "exists and was not written by dynref synth (no synth.yaml naming the generator); refusing to overwrite");
  staging.Commit();
  SynthStats stats;
  stats.frames = n;
  stats.render_ms_per_frame = render_ms / std::max(1, n);
  stats.render_cpu_ms_per_frame = render_cpu_ms / std::max(1, n);
  stats.total_ms_per_frame = std::chrono::duration<double, std::milli>(Clock::now() - t_start).count() / std::max(1, n);
  stats.total_cpu_ms_per_frame = 1000.0 * double(std::clock() - cpu_start) / CLOCKS_PER_SEC / std::max(1, n);
  return stats;
}

}  // namespace dynref::synth
