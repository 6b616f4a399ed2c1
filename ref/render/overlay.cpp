#include "render/overlay.h"

#include <array>

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <system_error>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "io/sequence.h"
#include "render/colormap.h"

namespace dynref::render {
namespace {

const Rgb kBlack{0, 0, 0}, kWhite{255, 255, 255}, kGrey{150, 150, 150};
const Rgb kGtDynamic{255, 40, 40}, kGtStatic{255, 255, 255};
const Rgb kLoop{255, 0, 255};  // loop-closure keyframe: border and banner
// Instance colours by class id (Okabe & Ito palette, colour-blind safe).
const Rgb kInstanceColours[] = {{230, 159, 0}, {86, 180, 233}, {0, 158, 115}, {240, 228, 66},
                                {0, 114, 178}, {213, 94, 0}, {204, 121, 167}};

int Px(double v) { return static_cast<int>(std::floor(v + 0.5)); }

// Feature marker: kept = filled disc, rejected = cross, undecided = hollow square.
// r = half size: 5 normally, 3 in crowded frames.
void Marker(Canvas& c, int x, int y, Rgb col, int decision, int r = 5) {
  if (decision == 1) {
    c.Disc(x, y, r, kBlack);
    c.Disc(x, y, r - 1, col);
  } else if (decision == 0) {
    c.Line(x - r, y - r, x + r, y + r, kBlack, r == 5 ? 5 : 3);
    c.Line(x - r, y + r, x + r, y - r, kBlack, r == 5 ? 5 : 3);
    c.Line(x - r, y - r, x + r, y + r, col, r == 5 ? 3 : 1);
    c.Line(x - r, y + r, x + r, y - r, col, r == 5 ? 3 : 1);
  } else {
    c.Rect(x - r, y - r, x + r, y + r, kBlack, 1);
    c.Rect(x - r + 1, y - r + 1, x + r - 1, y + r - 1, col, r == 5 ? 3 : 2);
  }
}

// One of the 7 instance colours per id (map planes).
Rgb PaletteColour(int64_t id) { return kInstanceColours[id % 7]; }

Rgb InstanceColour(const DetectedInstance& inst) {
  return kInstanceColours[(inst.class_id < 0 ? 0 : inst.class_id) % 7];
}

void DrawInstance(Canvas& c, const FrameDetections& det, const DetectedInstance& inst) {
  const Rgb col = InstanceColour(inst);
  if (inst.has_mask && !det.instance_ids.empty()) {
    const cv::Mat& ids = det.instance_ids;
    for (int y = 0; y < ids.rows; ++y)
      for (int x = 0; x < ids.cols; ++x) {
        if (ids.at<uint16_t>(y, x) != inst.id) continue;
        const bool edge = x == 0 || y == 0 || x == ids.cols - 1 || y == ids.rows - 1 ||
                          ids.at<uint16_t>(y, x - 1) != inst.id || ids.at<uint16_t>(y, x + 1) != inst.id ||
                          ids.at<uint16_t>(y - 1, x) != inst.id || ids.at<uint16_t>(y + 1, x) != inst.id;
        if (edge) c.Set(x, y, col), c.Set(x + 1, y, col);
        else c.Blend(x, y, col, 40);
      }
  }
  c.Rect(Px(inst.x_min), Px(inst.y_min), Px(inst.x_max), Px(inst.y_max), col, 1);
}

// Class, confidence and the trace's verdict on i<frame>.<id>; drawn on top of the features.
void DrawInstanceLabel(Canvas& c, const DetectedInstance& inst, const OverlayFrame& frame) {
  const Rgb col = InstanceColour(inst);
  std::string label = inst.class_name + " " + FormatFixed(inst.confidence, 2);
  auto it = frame.instances.find(inst.id);
  if (it != frame.instances.end()) {
    if (it->second.has_prob) label += " p=" + FormatFixed(it->second.prob, 2);
    if (it->second.decision == 0) label += " rejected";
    if (it->second.decision == 1) label += " kept";
  }
  const int ly = std::max(Px(inst.y_min) - Canvas::TextHeight() - 2, 1);
  c.Label(Px(inst.x_min) + 2, ly, label, col);
}

void DrawShape(Canvas& c, const OverlayShape& s) {
  const Rgb col = s.has_prob ? Viridis(s.prob) : kGrey;
  if (s.kind == trace::EntityKind::kLineSample) {
    c.Line(Px(s.x0), Px(s.y0), Px(s.x1), Px(s.y1), kBlack, 5);
    c.Line(Px(s.x0), Px(s.y0), Px(s.x1), Px(s.y1), col, 3);
    if (s.decision == 0) {  // rejected line: cross at its midpoint
      const int mx = Px((s.x0 + s.x1) / 2), my = Px((s.y0 + s.y1) / 2);
      c.Line(mx - 5, my - 5, mx + 5, my + 5, kWhite, 3);
      c.Line(mx - 5, my + 5, mx + 5, my - 5, kWhite, 3);
    }
    return;
  }
  // A plane matched to a map plane gets that plane's colour (one colour per map plane id).
  const bool by_id = s.kind == trace::EntityKind::kPlane && s.landmark >= 0;
  const Rgb fill = by_id ? PaletteColour(s.landmark) : col;
  c.FillRect(Px(s.x0), Px(s.y0), Px(s.x1), Px(s.y1), fill, 60);
  c.Rect(Px(s.x0), Px(s.y0), Px(s.x1), Px(s.y1), fill, 2);
  std::string label = (s.kind == trace::EntityKind::kPlane ? "plane " : "region ") + s.entity;
  if (by_id) label += " mpl" + std::to_string(s.landmark);
  if (s.has_prob) label += " p=" + FormatFixed(s.prob, 2);
  if (s.decision == 0) label += " rejected";
  c.Label(Px(s.x0) + 4, Px(s.y0) + 4, label, kWhite);
}

// A frame whose keyframe closed a loop: an 8 px magenta border and a banner at the bottom left,
// "LOOP kf<keyframe> -> kf<loop keyframe>  moved <m> m" per loop.
void DrawLoops(Canvas& c, const std::vector<OverlayLoop>& loops) {
  if (loops.empty()) return;
  c.Rect(0, 0, c.width() - 1, c.height() - 1, kLoop, 8);
  for (size_t i = 0; i < loops.size(); ++i) {
    const OverlayLoop& l = loops[i];
    const std::string text = "LOOP kf" + std::to_string(l.keyframe) + " -> kf" + std::to_string(l.loop_keyframe) +
                             "  moved " + FormatFixed(l.moved_m, 3) + " m";
    const int y = c.height() - 14 - (Canvas::TextHeight(2) + 6) * static_cast<int>(loops.size() - i);
    c.FillRect(10, y - 3, 10 + Canvas::TextWidth(text, 2) + 8, y + Canvas::TextHeight(2) + 2, kBlack, 200);
    c.Text(14, y, text, kLoop, 2);
  }
}

void DrawLegend(Canvas& c, bool gt) {
  const int w = 236, h = gt ? 112 : 80;
  const int x0 = c.width() - w - 6, y0 = c.height() - h - 6;
  c.FillRect(x0, y0, x0 + w, y0 + h, kBlack, 170);
  c.Text(x0 + 6, y0 + 4, "p(dynamic)", kWhite);
  for (int i = 0; i <= 200; ++i) c.FillRect(x0 + 18 + i, y0 + 20, x0 + 18 + i, y0 + 30, Viridis(i / 200.0));
  c.Text(x0 + 14, y0 + 32, "0", kWhite);
  c.Text(x0 + 106, y0 + 32, "0.5", kWhite);
  c.Text(x0 + 214, y0 + 32, "1", kWhite);
  const int my = y0 + 56;
  Marker(c, x0 + 12, my, Viridis(0.5), 1);
  c.Text(x0 + 22, my - 7, "kept", kWhite);
  Marker(c, x0 + 70, my, Viridis(0.5), 0);
  c.Text(x0 + 80, my - 7, "rejected", kWhite);
  Marker(c, x0 + 160, my, Viridis(0.5), -1);
  c.Text(x0 + 170, my - 7, "open", kWhite);
  c.Disc(x0 + 12, my + 18, 4, kGrey);
  c.Text(x0 + 22, my + 11, "no p traced", kWhite);
  if (gt) {
    c.Ring(x0 + 12, my + 40, 8, 3, kGtDynamic);
    c.Text(x0 + 24, my + 33, "GT dynamic", kWhite);
    c.Ring(x0 + 124, my + 40, 8, 1, kGtStatic);
    c.Text(x0 + 136, my + 33, "GT static", kWhite);
  }
}

void DrawMaskLayers(Canvas& c, const MaskLayerView& v) {
  if (v.legend == nullptr || v.legend->empty()) return;
  std::array<const MaskLayer*, 256> by_value{};
  for (const MaskLayer& l : *v.legend) by_value[size_t(l.value)] = &l;
  if (!v.labels.empty())
    for (int y = 0; y < std::min(v.labels.rows, c.height()); ++y) {
      const uint8_t* row = v.labels.ptr<uint8_t>(y);
      for (int x = 0; x < std::min(v.labels.cols, c.width()); ++x)
        if (const MaskLayer* l = by_value[row[x]]) c.Blend(x, y, Rgb{uint8_t(l->r), uint8_t(l->g), uint8_t(l->b)}, 90);
    }
  // Legend of the layers, top right.
  int w = 0;
  for (const MaskLayer& l : *v.legend) w = std::max(w, Canvas::TextWidth(l.name));
  w += 30;
  const int h = 16 * int(v.legend->size()) + 6, x0 = c.width() - w - 6, y0 = 6;
  c.FillRect(x0, y0, x0 + w, y0 + h, kBlack, 170);
  for (size_t i = 0; i < v.legend->size(); ++i) {
    const MaskLayer& l = (*v.legend)[i];
    const int y = y0 + 4 + 16 * int(i);
    c.FillRect(x0 + 5, y + 2, x0 + 17, y + 12, Rgb{uint8_t(l.r), uint8_t(l.g), uint8_t(l.b)});
    c.Text(x0 + 24, y, l.name, kWhite);
  }
}

}  // namespace

Canvas RenderOverlay(const cv::Mat& bgr, const OverlayFrame& frame, const FrameDetections* detections,
                     const GtFrame* gt, const MaskLayerView* layers) {
  Canvas c = Canvas::FromBgr(bgr);
  if (layers) DrawMaskLayers(c, *layers);
  if (detections)
    for (const DetectedInstance& inst : detections->instances) DrawInstance(c, *detections, inst);
  for (const OverlayShape& s : frame.shapes) DrawShape(c, s);
  int tp = 0, fp = 0, fn = 0, tn = 0;
  const bool crowded = frame.features.size() > 300;  // smaller markers and rings
  const int mr = crowded ? 3 : 5, ring = crowded ? 6 : 10;
  for (const OverlayFeature& f : frame.features) {
    const int x = Px(f.u), y = Px(f.v);
    if (gt) {
      const bool gt_dyn = gt->IsDynamic(f.u, f.v);
      // Predicted dynamic: rejected, or (no decision) probability >= 0.5.
      const bool pred = f.decision == 0 || (f.decision < 0 && f.has_prob && f.prob >= 0.5);
      (gt_dyn ? (pred ? tp : fn) : (pred ? fp : tn))++;
      c.Ring(x, y, ring, gt_dyn ? (crowded ? 2 : 3) : 1, gt_dyn ? kGtDynamic : kGtStatic);
    }
    if (f.has_prob) Marker(c, x, y, Viridis(f.prob), f.decision, mr);
    else c.Disc(x, y, mr - 1, kGrey);
  }
  if (detections)
    for (const DetectedInstance& inst : detections->instances) DrawInstanceLabel(c, inst, frame);
  // Text panel: frame, stamp, counts.
  std::vector<std::string> lines = {"frame " + std::to_string(frame.frame) + "  t=" +
                                        (frame.stamp_text.empty() ? FormatDouble17(frame.timestamp)
                                                                  : frame.stamp_text),
                                    "features " + std::to_string(frame.features.size())};
  if (gt)
    lines.push_back("vs GT: TP " + std::to_string(tp) + " FP " + std::to_string(fp) + " FN " +
                    std::to_string(fn) + " TN " + std::to_string(tn));
  for (const auto& [name, value] : frame.counts) {
    if (lines.size() >= 11) {
      lines.push_back("...");
      break;
    }
    lines.push_back(name + " " + std::to_string(value));
  }
  size_t wmax = 0;
  for (const auto& l : lines) wmax = std::max(wmax, l.size());
  c.FillRect(0, 0, Canvas::TextWidth(std::string(wmax, ' ')) + 10,
             static_cast<int>(lines.size()) * 16 + 6, kBlack, 170);
  for (size_t i = 0; i < lines.size(); ++i) c.Text(5, 4 + 16 * static_cast<int>(i), lines[i], kWhite);
  DrawLegend(c, gt != nullptr);
  DrawLoops(c, frame.loops);
  return c;
}

Canvas Montage(const std::vector<Canvas>& tiles, int columns) {
  if (tiles.empty()) return Canvas(1, 1, kBlack);
  columns = std::max(1, std::min<int>(columns, static_cast<int>(tiles.size())));
  const int rows = (static_cast<int>(tiles.size()) + columns - 1) / columns;
  int tw = 0, th = 0;
  for (const Canvas& t : tiles) tw = std::max(tw, t.width()), th = std::max(th, t.height());
  const int gap = 4;
  Canvas m(columns * tw + (columns + 1) * gap, rows * th + (rows + 1) * gap, Rgb{30, 30, 30});
  for (size_t i = 0; i < tiles.size(); ++i) {
    const int col = static_cast<int>(i) % columns, row = static_cast<int>(i) / columns;
    m.Paste(tiles[i], gap + col * (tw + gap), gap + row * (th + gap));
  }
  return m;
}

std::vector<std::string> RenderRunOverlays(const std::string& run_dir, int64_t first, int64_t last,
                                           const OverlayOptions& options) {
  // Everything that can be checked is checked before any output folder is created.
  if (first > last) throw InputError("--frames", "first frame after last");
  if (options.montage_columns < 1)
    throw InputError("--montage-columns", "must be >= 1 (got " + std::to_string(options.montage_columns) + ")");
  const RunInfo info = ReadRunInfo(run_dir);
  trace::TraceReader reader(info.trace_path);
  if (reader.level() != trace::Level::kFull)
    throw InputError(info.trace_path, std::string("overlays need a full trace (this one is ") +
                                          trace::LevelName(reader.level()) + ")");
  SequenceOptions so;
  so.camera = info.camera;
  const Sequence seq = OpenSequence(info.sequence, so);
  std::unique_ptr<DetectionsReader> det;
  if (!info.detections.empty()) det = std::make_unique<DetectionsReader>(info.detections);
  std::unique_ptr<GroundTruthLabels> gt;
  if (options.gt) gt = std::make_unique<GroundTruthLabels>(info.sequence);
  // A method's mask layers (RUN/masks/, io/mask_layers.h), when the run folder has them.
  std::unique_ptr<MaskLayersReader> layers;
  if (MaskLayersReader::Exists(run_dir + "/masks")) layers = std::make_unique<MaskLayersReader>(run_dir + "/masks");
  std::string out_dir = options.out_dir;
  if (out_dir.empty()) {
    struct stat st {};
    const bool is_dir = ::stat(run_dir.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
    out_dir = (is_dir ? run_dir : std::string(".")) + "/overlays";
  }
  {
    std::error_code ec;
    if (std::filesystem::exists(out_dir, ec) && !std::filesystem::is_directory(out_dir, ec))
      throw InputError(out_dir, "exists and is not a directory");
  }
  const std::vector<OverlayFrame> frames = CollectOverlayFrames(reader, first, last);
  // A closed range must lie inside the traced frames (README: out-of-range --frames is an error;
  // 38-45 on a 40-frame run was clipped silently, issue 20 item 11).
  if (last != std::numeric_limits<int64_t>::max() && (frames.empty() || frames.back().frame < last || frames.front().frame > first))
    throw InputError("--frames", std::to_string(first) + "-" + std::to_string(last) +
                                     " is not inside the run's traced frames" +
                                     (frames.empty() ? std::string() : " (this range has " + std::to_string(frames.front().frame) + "-" +
                                                                           std::to_string(frames.back().frame) + ")"));
  if (frames.empty())
    throw InputError(info.trace_path, "no traced frame in " + std::to_string(first) + "-" +
                                          std::to_string(last));
  for (const OverlayFrame& of : frames)
    if (of.frame < 0 || of.frame >= static_cast<int64_t>(seq.frames.size()))
      throw InputError(info.trace_path, "frame " + std::to_string(of.frame) + " is not in " +
                                            info.sequence + " (" + std::to_string(seq.frames.size()) +
                                            " frames)");
  // Rendered into a staging folder; the PNGs move in only when every frame was drawn, so a
  // failure (bad frame, unreadable RGB, disk full) leaves no partial overlays behind.
  StagingDirectory staging(out_dir);
  std::vector<std::string> names;  // "overlay_<frame>.png" in staging.dir()
  std::vector<Canvas> tiles;
  for (const OverlayFrame& of : frames) {
    const FrameEntry& fe = seq.frames[static_cast<size_t>(of.frame)];
    const cv::Mat bgr = LoadRgb(seq, fe);
    OverlayFrame shown = of;
    shown.stamp_text = fe.rgb_stamp_text;
    FrameDetections fd;
    const bool has_det = det && det->Has(fe.rgb_stamp_text);
    if (has_det) fd = det->Read(fe.rgb_stamp_text);
    GtFrame g;
    if (gt && gt->Has(fe.rgb_stamp_text)) {
      g.instance_ids = gt->Read(fe.rgb_stamp_text).instance_ids;
      g.moving = gt->Moving(fe.rgb_stamp_text);
    }
    MaskLayerView lv;
    if (layers) {
      lv.legend = &layers->legend();
      lv.labels = layers->Read(fe.rgb_stamp_text, bgr.size());
    }
    Canvas c = RenderOverlay(bgr, shown, has_det ? &fd : nullptr, gt ? &g : nullptr, layers ? &lv : nullptr);
    char name[64];
    std::snprintf(name, sizeof(name), "overlay_%06lld.png", static_cast<long long>(of.frame));
    c.WritePng(staging.dir() + "/" + name);
    names.push_back(name);
    if (!options.montage_path.empty()) tiles.push_back(std::move(c));
  }
  // All frames rendered: the montage (atomic on its own), then the frames into out_dir.
  if (!options.montage_path.empty()) {  // its folder may be out_dir itself, not made yet
    const std::string parent = std::filesystem::path(options.montage_path).parent_path().string();
    if (!parent.empty()) EnsureDirectory(parent);
    Montage(tiles, options.montage_columns).WritePng(options.montage_path);
  }
  EnsureDirectory(out_dir);
  std::vector<std::string> written;
  for (const std::string& name : names) {
    AtomicRename(staging.dir() + "/" + name, out_dir + "/" + name);
    written.push_back(out_dir + "/" + name);
  }
  staging.Commit();
  if (!options.montage_path.empty()) written.push_back(options.montage_path);
  return written;
}

}  // namespace dynref::render
