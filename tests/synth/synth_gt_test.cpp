// The ground truth of dynref synth is true (issue 3, item 8): depth back-projected with the GT
// pose lands on the scene surfaces, instance boundaries are depth discontinuities, static pixels
// re-project between frames with the GT poses, people and the scene carry ORB features.
#include <catch2/catch.hpp>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "io/mask_format.h"
#include "io/sequence.h"
#include "synth/sensor.h"
#include "synth/synth.h"
#include "synth/world.h"
#include "test_support.h"
#include "io/image_file.h"

namespace {

using namespace dynref;

Sequence Make(const std::string& name, const std::string& preset, int frames) {
  const std::string dir = test::ScratchDir(name);
  synth::SynthOptions o;
  o.preset = preset, o.frames = frames, o.out = dir;
  synth::GenerateSequence(o);
  return OpenSequence(dir);
}

Eigen::Vector3d BackProject(const Camera& c, int x, int y, double z) {
  return {(x - c.cx) / c.fx * z, (y - c.cy) / c.fy * z, z};
}

// 4-sigma of the Kinect model plus half a quantisation step.
double Tolerance(double z) { return 4 * synth::SensorModel().SigmaZ(z) + 0.5 / 5000.0; }

}  // namespace

TEST_CASE("synth: depth back-projected with the GT pose lands on the floor and on the rendered surfaces") {
  const Sequence seq = Make("synth_gt_surface", "walking_xyz", 2);
  const synth::World world(synth::GetPreset("walking_xyz"), 1);
  // The synthetic camera (TUM fr3 intrinsics) in the renderer's float form, as synth.cpp builds it.
  const Camera cam = CameraPreset("synthetic");
  const synth::Intrinsics K{float(cam.fx), float(cam.fy), float(cam.cx), float(cam.cy), 0.f, cam.width, cam.height};
  for (size_t i = 0; i < seq.frames.size(); ++i) {
    const cv::Mat depth = LoadDepthMeters(seq, seq.frames[i]);
    const SE3& T_wc = seq.groundtruth[i].T_wc;
    // Independent re-render at the pose read back from groundtruth.txt (rounded to 1e-6).
    std::vector<synth::DrawItem> items;
    world.Items(seq.frames[i].rgb_stamp - synth::kStampBase, &items);
    synth::GBuffer gb;
    synth::Rasterize(K, T_wc.inverse(), items, &gb);
    int floor_n = 0, floor_ok = 0, surf_n = 0, surf_ok = 0;
    for (int y = 0; y < 480; ++y)
      for (int x = 0; x < 640; ++x) {
        const double z = depth.at<float>(y, x);
        if (z <= 0) continue;
        const size_t idx = size_t(y) * 640 + x;
        const double zr = gb.z[idx];
        ++surf_n;
        if (std::abs(z - zr) < Tolerance(zr) + 0.002) ++surf_ok;  // 2 mm: pose rounding at 4 m
        const Eigen::Vector3d p_w = T_wc * BackProject(seq.camera, x, y, z);
        if (gb.face[idx] >= 0 && gb.faces[size_t(gb.face[idx])].material == 0) {  // material 0 = carpet
          ++floor_n;
          const double dz = std::abs(p_w.z());
          if (dz < Tolerance(z) + 0.002) ++floor_ok;  // the floor is the plane z = 0
        }
      }
    INFO("frame " << i << " surface " << surf_ok << "/" << surf_n << " floor " << floor_ok << "/" << floor_n);
    CHECK(surf_n > 200000);
    CHECK(floor_n > 20000);
    CHECK(surf_ok > 0.995 * surf_n);
    CHECK(floor_ok > 0.99 * floor_n);
  }
}

TEST_CASE("synth: person boundaries are depth discontinuities") {
  const Sequence seq = Make("synth_gt_edges", "walking_xyz", 1);
  const DetectionsReader gt(seq.root + "/gt");
  const FrameDetections det = gt.Read(seq.frames[0].rgb_stamp_text);
  const cv::Mat depth = LoadDepthMeters(seq, seq.frames[0]);
  int pairs = 0, jumps = 0;
  for (const auto& d : det.instances) {
    if (d.class_id != 0) continue;
    const cv::Mat& ids = det.instance_ids;
    for (int y = 3; y < 477; ++y)
      for (int x = 3; x < 637; ++x) {
        if (ids.at<uint16_t>(y, x) != d.id || ids.at<uint16_t>(y, x + 1) == d.id) continue;
        // Right boundary of the person: compare the nearest valid depths on either side.
        double zin = 0, zout = 0;
        for (int k = 0; k < 3 && zin == 0; ++k) zin = depth.at<float>(y, x - k);
        for (int k = 1; k < 4 && zout == 0; ++k) zout = ids.at<uint16_t>(y, x + k) != d.id ? depth.at<float>(y, x + k) : 0;
        if (zin == 0 || zout == 0) continue;
        ++pairs;
        if (std::abs(zout - zin) > 0.05) ++jumps;
      }
  }
  INFO(jumps << " of " << pairs);
  CHECK(pairs > 200);
  CHECK(jumps > 0.85 * pairs);  // the rest: feet on the floor, hand against the chair
}

TEST_CASE("synth: static pixels re-project between frames with the GT poses") {
  const Sequence seq = Make("synth_gt_reproj", "walking_xyz", 4);
  const DetectionsReader gt(seq.root + "/gt");
  const cv::Mat z0 = LoadDepthMeters(seq, seq.frames[0]), z1 = LoadDepthMeters(seq, seq.frames[3]);
  cv::Mat g0, g1;
  cv::cvtColor(LoadRgb(seq, seq.frames[0]), g0, cv::COLOR_BGR2GRAY);
  cv::cvtColor(LoadRgb(seq, seq.frames[3]), g1, cv::COLOR_BGR2GRAY);
  const cv::Mat m0 = dynref::ImageRead(seq.root + "/gt/motion/" + seq.frames[0].rgb_stamp_text + ".png", cv::IMREAD_GRAYSCALE);
  const cv::Mat m1 = dynref::ImageRead(seq.root + "/gt/motion/" + seq.frames[3].rgb_stamp_text + ".png", cv::IMREAD_GRAYSCALE);
  REQUIRE(cv::countNonZero(m0) > 1000);  // people are moving in these frames
  const SE3 T_10 = seq.groundtruth[3].T_wc.inverse() * seq.groundtruth[0].T_wc;
  int n = 0, ok = 0;
  std::vector<int> photo;
  for (int y = 0; y < 480; y += 2)
    for (int x = 0; x < 640; x += 2) {
      const double z = z0.at<float>(y, x);
      if (z <= 0 || m0.at<uint8_t>(y, x)) continue;
      const Eigen::Vector3d p1 = T_10 * BackProject(seq.camera, x, y, z);
      const int u = int(std::lround(seq.camera.fx * p1.x() / p1.z() + seq.camera.cx));
      const int v = int(std::lround(seq.camera.fy * p1.y() / p1.z() + seq.camera.cy));
      if (u < 1 || v < 1 || u > 638 || v > 478) continue;
      const double zo = z1.at<float>(v, u);
      if (zo <= 0 || m1.at<uint8_t>(v, u) || zo < p1.z() - 0.1) continue;  // occluded or moving now
      ++n;
      // Rounding to the nearest pixel moves up to 0.7 px along a slanted surface: allow 2 cm.
      if (std::abs(zo - p1.z()) < 2 * Tolerance(p1.z()) + 0.02) ++ok;
      photo.push_back(std::abs(int(g0.at<uint8_t>(y, x)) - int(g1.at<uint8_t>(v, u))));
    }
  std::nth_element(photo.begin(), photo.begin() + long(photo.size() / 2), photo.end());
  INFO(ok << " of " << n << ", median |dI| " << photo[photo.size() / 2]);
  CHECK(n > 30000);
  CHECK(ok > 0.97 * n);
  CHECK(photo[photo.size() / 2] < 12);
}

TEST_CASE("synth: over 1000 ORB features per frame and over 50 on a near person") {
  const Sequence seq = Make("synth_gt_orb", "walking_xyz", 1);
  const DetectionsReader gt(seq.root + "/gt");
  const FrameDetections det = gt.Read(seq.frames[0].rgb_stamp_text);
  cv::Mat gray;
  cv::cvtColor(LoadRgb(seq, seq.frames[0]), gray, cv::COLOR_BGR2GRAY);
  std::vector<cv::KeyPoint> kps;
  cv::ORB::create(1500)->detect(gray, kps);
  CHECK(kps.size() > 1000);
  std::vector<cv::KeyPoint> fast;
  cv::FAST(gray, fast, 20);
  CHECK(fast.size() > 2000);
  // The largest person in view.
  int best = 0;
  double best_area = 0;
  for (const auto& d : det.instances) {
    const double area = (d.x_max - d.x_min) * (d.y_max - d.y_min);
    if (d.class_id == 0 && area > best_area) best = d.id, best_area = area;
  }
  REQUIRE(best > 0);
  const cv::Mat mask = det.MaskOf(best);
  int on_person = 0;
  cv::ORB::create(2000)->detect(gray, kps);
  for (const auto& k : kps) on_person += mask.at<uint8_t>(cvRound(k.pt.y), cvRound(k.pt.x)) ? 1 : 0;
  INFO("ORB " << kps.size() << ", on person " << best << ": " << on_person);
  CHECK(on_person > 50);
  // The office without people too, from the static_halfsphere viewpoint.
  const Sequence s2 = Make("synth_gt_orb_static", "static_halfsphere", 1);
  cv::cvtColor(LoadRgb(s2, s2.frames[0]), gray, cv::COLOR_BGR2GRAY);
  cv::ORB::create(1500)->detect(gray, kps);
  CHECK(kps.size() > 1000);
}

TEST_CASE("synth: a seated person's legs stay still while arms move and the rolled chair moves in bursts") {
  const synth::World world(synth::GetPreset("sitting_static"), 1);
  // Item order: 0 room, then per actor its 11 body parts followed by its chair.
  const size_t a0 = 1, chair0 = a0 + synth::kBodyPartCount, a1 = chair0 + 1, chair1 = a1 + synth::kBodyPartCount;
  REQUIRE(world.ItemCount() == chair1 + 1);
  CHECK(world.ItemInstance(a0) == 1);
  CHECK(world.ItemInstance(chair1) == 21);
  int arm_moves = 0, leg_moves = 0, chair0_moves = 0, chair1_moves = 0, chair1_still = 0;
  std::vector<synth::DrawItem> now, before;
  for (int i = 1; i < 300; i += 3) {
    const double t = i / 30.0;
    world.Items(t, &now);
    world.Items(t - 1 / 30.0, &before);
    const auto moved = [&](size_t k) {
      return (now[k].T_wo.translation() - before[k].T_wo.translation()).norm() > 1e-4 ||
             !now[k].T_wo.linear().isApprox(before[k].T_wo.linear(), 1e-6);
    };
    arm_moves += moved(a0 + synth::kForearmL) || moved(a0 + synth::kForearmR);
    for (int leg : {synth::kThighL, synth::kThighR, synth::kShinL, synth::kShinR}) leg_moves += moved(a0 + size_t(leg));
    chair0_moves += moved(chair0);
    chair1_moves += moved(chair1);
    chair1_still += !moved(chair1);
  }
  INFO("arm " << arm_moves << " leg " << leg_moves << " chair1 moving " << chair1_moves << " still " << chair1_still);
  CHECK(arm_moves > 20);
  CHECK(leg_moves == 0);
  CHECK(chair0_moves == 0);
  CHECK(chair1_moves > 10);
  CHECK(chair1_still > 10);
}
