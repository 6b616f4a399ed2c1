// epi.nerf (map module): seed 004 Sec. 3.3.2, the NeRF thread's input (nerf_export.h). Each
// keyframe keeps its colour image, the masks epi.vote declared dynamic and its static keypoints
// (those no stage excluded: epi.vote excludes every keypoint of a dynamic mask). At the end of the run, with the final
// keyframe poses, each keyframe is matched to the previous surviving one by MNN2 on the ORB
// descriptors, the matches are triangulated (DLT + gates) into the pseudo-point cloud, and
// RUN/nerf/ is written: images/<stamp>.png, masks/<stamp>.png (nerfstudio: 255 = use the pixel,
// 0 = dynamic), sparse_points.ply and transforms.json (last, atomically) with L_geo and the gate
// counts under "dynref".
#include <cmath>
#include <filesystem>
#include <utility>

#include "core/atomic_file.h"
#include "core/error.h"
#include "io/ply.h"
#include "dynamic/epi/stages.h"
#include "map/map.h"
#include "io/image_file.h"

namespace dynref::epi {

NerfModule::NerfModule(const ParamMap& p, std::shared_ptr<Blackboard> board) : board_(std::move(board)) {
  p.RequireKnownKeys({"parallax_cos_max", "reprojection_px", "mnn_ratio"});
  gates_.parallax_cos_max = p.GetDouble("parallax_cos_max");
  gates_.reprojection_px = p.GetDouble("reprojection_px");
  match_.ratio = p.GetDouble("mnn_ratio");
  try {
    gates_.Check();
    if (!(match_.ratio > 0 && match_.ratio <= 1)) throw std::invalid_argument("mnn_ratio must be in (0, 1]");
  } catch (const std::invalid_argument& e) {
    throw InputError(p.file, p.line, "map module epi.nerf: " + std::string(e.what()));
  }
}

void NerfModule::OnKeyFrame(const MapModuleContext& ctx) {
  const Frame& f = ctx.frame;
  camera_ = ctx.camera;  // one camera per run
  Keyframe k;
  k.stamp_text = f.stamp_text;
  k.rgb = f.rgb.clone();
  if (board_->Has(f)) k.dynamic_mask = board_->DynamicMask();
  // Static keypoints: epi.vote has excluded every keypoint of a mask it voted dynamic.
  std::vector<int> rows;
  for (int i = 0; i < static_cast<int>(f.N()); ++i) {
    if (f.IsExcluded(i)) continue;
    k.raw.push_back(f.keys[static_cast<size_t>(i)].pt);
    k.un.push_back(f.keys_un[static_cast<size_t>(i)].pt);
    rows.push_back(i);
  }
  k.features = rows;
  k.frame_index = f.index;
  trace_ = &ctx.trace;
  // MNN2's absolute gate in the descriptors' own unit: the extractor's TH_HIGH, as the backbone's
  // MNN2 uses it (features/mnn2.h; ORB 100 bits, SIFT 0.60 squared L2 of unit rows). Issue 38: a
  // bit count alone left SIFT at the ORB-equivalent 1.5625, above SIFT's wrong-match p95.
  match_.tau_bits = static_cast<int>(std::lround(f.match_profile.th_high));
  match_.tau_float = f.match_profile.th_high;
  k.descriptors.create(static_cast<int>(rows.size()), f.descriptors.cols, f.descriptors.type());
  for (size_t r = 0; r < rows.size(); ++r) f.descriptors.row(rows[r]).copyTo(k.descriptors.row(static_cast<int>(r)));
  ctx.trace.FrameCount(name(), "static_keypoints", static_cast<int64_t>(rows.size()));
  keyframes_[ctx.keyframe.id] = std::move(k);
}

void NerfModule::OnMapUpdate(const MapModuleContext& ctx) {
  for (auto it = keyframes_.begin(); it != keyframes_.end();) {
    const KeyFrame* kf = ctx.map.kf(it->first);
    it = (kf == nullptr || kf->bad) ? keyframes_.erase(it) : std::next(it);
  }
}

void NerfModule::Finish(const Map& map, RunEnd& end) {
  if (keyframes_.empty() || end.out_dir().empty()) return;
  const std::string dir = end.out_dir() + "/nerf";
  std::filesystem::create_directories(dir + "/images");
  std::filesystem::create_directories(dir + "/masks");
  std::vector<NerfFrame> frames;
  PointCloud cloud;
  int64_t counts[5] = {0, 0, 0, 0, 0}, matches = 0, l_geo_terms = 0;
  double l_geo_sum = 0;
  const Keyframe* prev = nullptr;
  int64_t prev_id = -1;
  SE3 prev_T_cw = SE3::Identity();
  const bool full = trace_ != nullptr && trace_->full_enabled();
  for (const auto& [id, k] : keyframes_) {
    const KeyFrame* kf = map.kf(id);
    if (kf == nullptr || kf->bad) continue;
    const SE3 T_cw = kf->T_cw;
    if (full) {  // the exported keyframe: its final pose (the matches' gates are recomputed with it)
      std::vector<trace::NamedValue> in = {{"frame", double(k.frame_index)}, {"ref_kf", double(prev_id)}};
      const Eigen::Matrix3d R = T_cw.linear();
      const Eigen::Vector3d t = T_cw.translation();
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) in.push_back({"R" + std::to_string(r) + std::to_string(c), R(r, c)});
      for (int r = 0; r < 3; ++r) in.push_back({"t" + std::to_string(r), t(r)});
      trace_->ProbabilityUpdate(name(), trace::EntityKind::kKeyFrame, "kf" + std::to_string(id), in, 0.0, 0.0);
    }
    const std::string image = "images/" + k.stamp_text + ".png", mask = "masks/" + k.stamp_text + ".png";
    if (!dynref::ImageWrite(dir + "/" + image, k.rgb)) throw std::runtime_error("cannot write " + dir + "/" + image);
    cv::Mat keep(k.rgb.size(), CV_8U, cv::Scalar(255));
    if (!k.dynamic_mask.empty()) keep.setTo(0, k.dynamic_mask);
    if (!dynref::ImageWrite(dir + "/" + mask, keep)) throw std::runtime_error("cannot write " + dir + "/" + mask);
    frames.push_back({image, mask, T_cw, static_cast<int>(id)});
    if (prev != nullptr && !k.descriptors.empty() && !prev->descriptors.empty()) {
      for (const features::DescriptorMatch& m : features::MatchMnn2(k.descriptors, prev->descriptors, match_)) {
        ++matches;
        const cv::Point2f& a = k.un[static_cast<size_t>(m.i)];
        const cv::Point2f& b = prev->un[static_cast<size_t>(m.j)];
        Eigen::Vector3d X;
        TriangulationValues tv;
        const Triangulated t =
            TriangulateDlt(camera_.Pinhole(), T_cw, prev_T_cw, {a.x, a.y}, {b.x, b.y}, gates_, &X, &tv);
        ++counts[static_cast<int>(t)];
        if (full)  // the match (MNN2 distances) and what each gate tested; outcome = Triangulated
          trace_->ProbabilityUpdate(
              name(), trace::EntityKind::kFeature,
              "f" + std::to_string(k.frame_index) + "." + std::to_string(k.features[static_cast<size_t>(m.i)]),
              {{"kf", double(id)}, {"ref_kf", double(prev_id)},
               {"ref_feature", double(prev->features[static_cast<size_t>(m.j)])}, {"distance", m.distance},
               {"second", m.second}, {"rho", match_.ratio},
               {"tau", k.descriptors.type() == CV_8U ? double(match_.tau_bits) : match_.tau_float},
               {"u", double(a.x)}, {"v", double(a.y)}, {"ref_u", double(b.x)}, {"ref_v", double(b.y)},
               {"cos_parallax", tv.cos_parallax}, {"X", tv.X.x()}, {"Y", tv.X.y()}, {"Z", tv.X.z()},
               {"z", tv.z0}, {"ref_z", tv.z1}, {"err_px", tv.err0}, {"ref_err_px", tv.err1},
               {"outcome", double(static_cast<int>(t))}},
              0.0, 0.0);
        if (t != Triangulated::kOk) continue;
        Eigen::Vector3d c;
        const cv::Point2f& raw = k.raw[static_cast<size_t>(m.i)];
        if (!SampleRgb(k.rgb, raw.x, raw.y, &c)) continue;
        ColoredPoint p;
        p.x = static_cast<float>(X.x()), p.y = static_cast<float>(X.y()), p.z = static_cast<float>(X.z());
        p.r = static_cast<uint8_t>(std::lround(c.x() * 255)), p.g = static_cast<uint8_t>(std::lround(c.y() * 255)),
        p.b = static_cast<uint8_t>(std::lround(c.z() * 255));
        cloud.push_back(p);
        // L_geo over both views the point was triangulated from.
        for (const auto& [image_bgr, pose] : {std::pair<const cv::Mat*, SE3>{&k.rgb, T_cw}, {&prev->rgb, prev_T_cw}}) {
          const Eigen::Vector2d u = camera_.Pinhole().Project(pose * X);
          const cv::Point2d raw_px = camera_.Distort(u.x(), u.y());
          Eigen::Vector3d seen;
          if (!SampleRgb(*image_bgr, raw_px.x, raw_px.y, &seen)) continue;
          l_geo_sum += (seen - c).squaredNorm();
          ++l_geo_terms;
        }
      }
    }
    prev = &k;
    prev_id = id;
    prev_T_cw = T_cw;
  }
  WritePly(dir + "/sparse_points.ply", cloud, PlyFormat::kBinaryLittleEndian,
           "dynref epi.nerf pseudo-point cloud (seed 004 Sec. 3.3.2)");
  nlohmann::json extra;
  extra["l_geo"] = l_geo_terms > 0 ? l_geo_sum / static_cast<double>(l_geo_terms) : 0.0;
  extra["l_geo_terms"] = l_geo_terms;
  extra["points"] = cloud.size();
  extra["keyframes"] = frames.size();
  extra["matches"] = matches;
  for (int t = 0; t < 5; ++t) extra["triangulation"][TriangulatedName(static_cast<Triangulated>(t))] = counts[t];
  extra["gates"] = {{"parallax_cos_max", gates_.parallax_cos_max}, {"reprojection_px", gates_.reprojection_px}};
  extra["axes"] = "transform_matrix: camera-to-world, OpenGL camera axes (x right, y up, z backwards)";
  AtomicWriteFile(dir + "/transforms.json", TransformsJson(camera_, frames, "sparse_points.ply", extra).dump(2) + "\n");
  end.AddOutput(name(), dir + "/transforms.json",
                std::to_string(frames.size()) + " keyframes, " + std::to_string(cloud.size()) +
                    " triangulated static points, L_geo " + std::to_string(extra["l_geo"].get<double>()));
}

}  // namespace dynref::epi
