// Verifiers of the motion-blur SLAM records (seed 003, Huai et al., Sensors 2025; spec 003;
// ref/verify/README.md "Motion-blur SLAM"): the missed-segmentation compensation (person
// association, least-squares corner prediction, pastes, tracks that end; Sec. 3.1), depth fusion
// (stratified samples, human value range, 3-sigma screen; Sec. 3.2), dilation (Sec. 4.5) and the
// k-d tree keypoint probabilities with their removals (Sec. 3.3, Eq. (20)). Written from the paper,
// the spec and ref/trace/README.md; never calls ref/dynamic/blur.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/rng.h"
#include "verify/verifier.h"

namespace dynref::verify {
namespace {

using trace::EntityKind;
using trace::Record;
using trace::RecordType;

constexpr const char* kMask = "blur.mask";
constexpr const char* kComp = "blur.compensation";
constexpr const char* kDepth = "blur.depth_fusion";
constexpr const char* kProb = "blur.probability";

// Inclusive pixel box (the records' x_min..y_max).
struct Box {
  int64_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;
  int64_t Area() const { return x1 < x0 || y1 < y0 ? 0 : (x1 - x0 + 1) * (y1 - y0 + 1); }
  Box Meet(const Box& o) const { return {std::max(x0, o.x0), std::max(y0, o.y0), std::min(x1, o.x1), std::min(y1, o.y1)}; }
  bool operator==(const Box& o) const { return x0 == o.x0 && y0 == o.y0 && x1 == o.x1 && y1 == o.y1; }
};

Box BoxOf(const Record& r) {
  return {int64_t(Input(r, "x_min").value_or(0)), int64_t(Input(r, "y_min").value_or(0)),
          int64_t(Input(r, "x_max").value_or(-1)), int64_t(Input(r, "y_max").value_or(-1))};
}

// Box IoU on pixel counts (the association of spec 003 E3).
double Iou(const Box& a, const Box& b) {
  const double i = double(a.Meet(b).Area()), u = double(a.Area()) + double(b.Area()) - i;
  return u > 0 ? i / u : 0.0;
}

// One track's state in one frame: a segmented person or a pasted prediction.
struct TrackState {
  size_t rec = 0;              // record index in the frame
  bool pasted = false;
  double cx = 0, cy = 0, t = 0;  // the corner the line fit uses and its time
  Box box;                     // the state's box (the next association starts from it)
  double ax = 0, ay = 0;       // its mask's anchor: box corner (person) or from + (dx, dy) (paste)
  int64_t consecutive = 0;     // frames in a row predicted (0 for a segmented person)
};

// The blur records of one frame group (indices into its records).
struct BlurFrame {
  bool blur = false;           // blur.mask ran here (its counts are present)
  bool has_stamp = false;
  double stamp = 0;
  std::map<std::string, int64_t> counts;      // blur.mask counts
  std::vector<size_t> persons, pastes, depth, keypoints;
  std::map<int64_t, TrackState> tracks;       // track id -> state
  std::map<std::string, size_t> prob_of;      // blur.probability PROB by entity (the last)
  std::map<std::string, size_t> removal_of;   // blur.probability DECISION by entity
  int64_t max_track_before = 0;               // largest track id in earlier frames
  bool samples_known = false;
  std::vector<std::pair<int64_t, int64_t>> samples;  // this frame's stratified sample positions
  std::map<std::pair<int64_t, int64_t>, std::vector<size_t>> grid;  // keypoints by D-cell
};

// Index of every blur record of a trace, built once per TraceModel (verifiers run one record at
// a time; the keypoint neighbourhoods and the track histories need the whole frame).
class BlurIndex {
 public:
  const std::vector<BlurFrame>& Of(const TraceModel& t) const {
    if (model_ != &t || data_ != t.frames().data() || frames_.size() != t.frames().size()) Build(t);
    return frames_;
  }

 private:
  void Build(const TraceModel& t) const {
    model_ = &t;
    data_ = t.frames().data();
    frames_.assign(t.frames().size(), BlurFrame());
    int64_t max_track = 0;
    const double radius = t.StageNumber(kProb, "radius_px").value_or(20);
    for (size_t p = 0; p < t.frames().size(); ++p) {
      BlurFrame& b = frames_[p];
      b.max_track_before = max_track;
      const auto& recs = t.frames()[p].records;
      for (size_t i = 0; i < recs.size(); ++i) {
        const Record& r = recs[i];
        if (r.type == RecordType::kFrame) b.has_stamp = true, b.stamp = r.timestamp;
        if (r.type == RecordType::kCount && r.stage == kMask) b.blur = true, b.counts[r.name] = r.value;
        if (r.type == RecordType::kDecision && r.stage == kProb) b.removal_of[r.entity] = i;
        if (r.type != RecordType::kProbability) continue;
        if (r.stage == kComp && r.kind == EntityKind::kInstanceMask) b.persons.push_back(i);
        if (r.stage == kComp && r.kind == EntityKind::kPixelRegion) b.pastes.push_back(i);
        if (r.stage == kDepth) b.depth.push_back(i);
        if (r.stage == kProb) {
          b.prob_of[r.entity] = i;
          b.keypoints.push_back(i);
          const double x = Input(r, "x").value_or(0), y = Input(r, "y").value_or(0);
          b.grid[{int64_t(std::floor(x / radius)), int64_t(std::floor(y / radius))}].push_back(i);
        }
        if (r.stage == kComp && (r.kind == EntityKind::kInstanceMask || r.kind == EntityKind::kPixelRegion)) {
          const auto track = Input(r, "track");
          if (!track) continue;
          TrackState s;
          s.rec = i;
          s.pasted = r.kind == EntityKind::kPixelRegion;
          s.box = BoxOf(r);
          s.cx = s.pasted ? Input(r, "to_x").value_or(0) : double(s.box.x0);
          s.cy = s.pasted ? Input(r, "to_y").value_or(0) : double(s.box.y0);
          s.t = s.pasted ? Input(r, "t_c").value_or(0) : Input(r, "t").value_or(0);
          s.consecutive = s.pasted ? int64_t(Input(r, "consecutive").value_or(0)) : 0;
          s.ax = s.pasted ? Input(r, "from_x").value_or(0) + Input(r, "dx").value_or(0) : double(s.box.x0);
          s.ay = s.pasted ? Input(r, "from_y").value_or(0) + Input(r, "dy").value_or(0) : double(s.box.y0);
          b.tracks[int64_t(*track)] = s;
          max_track = std::max(max_track, int64_t(*track));
        }
      }
    }
    // The stratified samples (spec 003 step 3): one draw of the "blur.depth_sampling" stream per
    // frame whose person boxes were fused, i.e. per frame with blur.depth_fusion records.
    const auto seed = t.StageNumber(kMask, "sampling_seed");
    const auto cols = t.StageNumber(kMask, "grid_cols"), rows = t.StageNumber(kMask, "grid_rows");
    const auto per_cell = t.StageNumber(kMask, "samples_per_cell");
    const int64_t w = t.camera().width, h = t.camera().height;
    if (!seed || !cols || !rows || !per_cell || !t.camera().present || w <= 0 || h <= 0) return;
    Rng rng(uint64_t(*seed), "blur.depth_sampling");
    for (BlurFrame& b : frames_) {
      if (b.depth.empty()) continue;
      b.samples_known = true;
      const int64_t nc = int64_t(*cols), nr = int64_t(*rows);
      for (int64_t r = 0; r < nr; ++r) {
        const int64_t y0 = r * h / nr, y1 = (r + 1) * h / nr;
        for (int64_t c = 0; c < nc; ++c) {
          const int64_t x0 = c * w / nc, x1 = (c + 1) * w / nc;
          if (x1 <= x0 || y1 <= y0) continue;
          for (int64_t s = 0; s < int64_t(*per_cell); ++s) {
            const int64_t y = rng.UniformInt(y0, y1 - 1);  // row first, then column (the stage's order)
            const int64_t x = rng.UniformInt(x0, x1 - 1);
            b.samples.emplace_back(x, y);
          }
        }
      }
    }
  }

  mutable const TraceModel* model_ = nullptr;
  mutable const FrameRecords* data_ = nullptr;
  mutable std::vector<BlurFrame> frames_;
};

double Config(const TraceModel& t, Check& c, const char* stage, const char* key) {
  return c.Need(t.StageNumber(stage, key), std::string("config ") + stage + "." + key);
}

// The previous frame group when blur.mask ran there (its tracks are this frame's candidates).
const BlurFrame* Previous(const std::vector<BlurFrame>& frames, size_t pos) {
  return pos > 0 && frames[pos - 1].blur ? &frames[pos - 1] : nullptr;
}

int64_t Count(const BlurFrame& b, Check& c, const std::string& name) {
  const auto it = b.counts.find(name);
  if (it == b.counts.end()) {
    c.Missing("count blur.mask " + name);
    return 0;
  }
  return it->second;
}

// Greedy association by box IoU >= iou_found, best pair first, ties by track id then person
// order (spec 003 E3); returns, per current person, the previous track found (-1: none).
std::vector<int64_t> Associate(const BlurFrame* prev, const std::vector<Box>& persons, double iou_found) {
  std::vector<int64_t> out(persons.size(), -1);
  if (prev == nullptr) return out;
  struct Pair {
    double iou;
    int64_t track;
    size_t person;
  };
  std::vector<Pair> pairs;
  for (const auto& [id, s] : prev->tracks)
    for (size_t b = 0; b < persons.size(); ++b) {
      const double iou = Iou(s.box, persons[b]);
      if (iou >= iou_found) pairs.push_back({iou, id, b});
    }
  std::stable_sort(pairs.begin(), pairs.end(), [](const Pair& x, const Pair& y) {
    if (x.iou != y.iou) return x.iou > y.iou;
    return x.track != y.track ? x.track < y.track : x.person < y.person;
  });
  std::map<int64_t, bool> used;
  for (const Pair& p : pairs) {
    if (used[p.track] || out[p.person] >= 0) continue;
    used[p.track] = true;
    out[p.person] = p.track;
  }
  return out;
}

// Least-squares line through (tau_j, x_j) with tau_j = t_j - t_c, evaluated at tau = 0 (spec 003
// step 2, E4): b = (sum x - k sum tau) / n, k = (n sum x tau - sum x sum tau) / (n sum tau^2 - (sum tau)^2).
// One sample (or equal times): the newest corner.
std::pair<double, double> FitCorner(const std::vector<std::array<double, 3>>& h, double t_c) {
  const double n = double(h.size());
  double st = 0, stt = 0, sx = 0, sy = 0, sxt = 0, syt = 0;
  for (const auto& s : h) {
    const double tau = s[2] - t_c;
    st += tau, stt += tau * tau, sx += s[0], sy += s[1], sxt += s[0] * tau, syt += s[1] * tau;
  }
  const double den = n * stt - st * st;
  if (h.size() < 2 || !(std::fabs(den) > 1e-18)) return {h.back()[0], h.back()[1]};
  const double k1 = (n * sxt - sx * st) / den, k2 = (n * syt - sy * st) / den;
  return {(sx - k1 * st) / n, (sy - k2 * st) / n};
}

// The track's last `history` states, oldest first, walking back from frame group `pos`.
std::vector<std::array<double, 3>> History(const std::vector<BlurFrame>& frames, size_t pos, int64_t track,
                                           int64_t history) {
  std::vector<std::array<double, 3>> h;
  for (size_t p = pos + 1; p-- > 0 && int64_t(h.size()) < history;) {
    if (!frames[p].blur) break;
    const auto it = frames[p].tracks.find(track);
    if (it == frames[p].tracks.end()) break;
    h.push_back({it->second.cx, it->second.cy, it->second.t});
  }
  std::reverse(h.begin(), h.end());
  return h;
}

// Pixel bookkeeping of M_sd that every compensation record of the frame shares: the segmenter
// and the pastes make A_after, pastes and fusion add disjoint pixels, dilation adds pixels
// exactly when it has a non-empty, non-full mask and a kernel.
void CheckFrameAreas(const TraceModel& t, const BlurFrame& b, const BlurFrame* prev, size_t pos, Check& c) {
  const auto& recs = t.frames()[pos].records;
  int64_t pasted = 0, added = 0;
  for (size_t i : b.pastes) pasted += int64_t(c.Need(recs[i], "pasted_px"));
  for (size_t i : b.depth) added += int64_t(c.Need(recs[i], "added_px"));
  const int64_t now = Count(b, c, "area_now"), before = Count(b, c, "area_before"), after = Count(b, c, "area_after");
  c.Near("count area_before", prev ? double(prev->counts.count("area_after") ? prev->counts.at("area_after") : -1) : 0.0,
         double(before));
  c.Near("count area_after", double(now + pasted), double(after));
  c.Near("count px_compensation", double(pasted), double(Count(b, c, "px_compensation")));
  c.Near("count px_segmenter", double(after - pasted), double(Count(b, c, "px_segmenter")));
  c.Near("count px_depth_fusion", double(added), double(Count(b, c, "px_depth_fusion")));
  const double size = Config(t, c, kMask, "dilation_size");
  const int64_t dil = Count(b, c, "px_dilation"), mask = after + added;
  const int64_t image = int64_t(t.camera().width) * t.camera().height;
  if (size == 0 || mask == 0 || mask == image) c.Near("count px_dilation", 0.0, double(dil));
  else if (dil <= 0) c.Near("count px_dilation (> 0: a non-empty mask grows)", 1.0, double(dil));
}

// r = A_c / A_(c-1) < r_threshold with compensation on (Sec. 3.1; A_(c-1) = 0: undefined, E1).
bool Triggered(const TraceModel& t, const BlurFrame& b, Check& c) {
  const double now = double(Count(b, c, "area_now")), before = double(Count(b, c, "area_before"));
  const double on = Config(t, c, kMask, "compensation"), thr = Config(t, c, kMask, "r_threshold");
  return on != 0 && before > 0 && now / before < thr;
}

bool FoundNow(const TraceModel& t, const BlurFrame& b, size_t pos, int64_t track) {
  for (size_t i : b.persons) {
    const Record& r = t.frames()[pos].records[i];
    if (Input(r, "track").value_or(-1) == double(track) && Input(r, "found").value_or(0) != 0) return true;
  }
  return false;
}

class BlurVerifier : public Verifier {
 public:
  explicit BlurVerifier(std::shared_ptr<BlurIndex> index) : index_(std::move(index)) {}

 protected:
  std::shared_ptr<BlurIndex> index_;
};

// blur.compensation on a segmented person i<frame>.<detection>: its association (E3).
class PersonVerifier : public BlurVerifier {
 public:
  using BlurVerifier::BlurVerifier;
  bool Claims(const Record& r) const override {
    return r.type == RecordType::kProbability && r.stage == kComp && r.kind == EntityKind::kInstanceMask;
  }
  void Verify(const TraceModel& t, RecordRef at, Check& c) const override {
    const auto& frames = index_->Of(t);
    const BlurFrame& b = frames[at.frame_pos];
    const BlurFrame* prev = Previous(frames, at.frame_pos);
    const Record& r = t.At(at);
    const auto& recs = t.frames()[at.frame_pos].records;
    const double iou_found = Config(t, c, kMask, "iou_found");
    for (const char* k : {"track", "found", "iou", "x_min", "y_min", "x_max", "y_max", "t"}) c.Need(r, k);
    if (!c.ok()) return;
    std::vector<Box> boxes;
    size_t me = 0;
    for (size_t i : b.persons) {
      if (i == at.index) me = boxes.size();
      boxes.push_back(BoxOf(recs[i]));
    }
    const std::vector<int64_t> track = Associate(prev, boxes, iou_found);
    int64_t next_new = b.max_track_before + 1;  // new tracks take the next ids, in person order
    for (size_t k = 0; k < me; ++k) next_new += track[k] < 0;
    const bool found = track[me] >= 0;
    c.Same("in.found", found, Input(r, "found").value() != 0);
    c.Near("in.track", double(found ? track[me] : next_new), *Input(r, "track"));
    c.Near("in.iou", found ? Iou(prev->tracks.at(track[me]).box, boxes[me]) : 0.0, *Input(r, "iou"));
    c.Near("in.t", b.has_stamp ? b.stamp : NAN, *Input(r, "t"), 0);
    const Box image{0, 0, t.camera().width - 1, t.camera().height - 1};
    if (t.camera().present && !(boxes[me].Meet(image) == boxes[me] && boxes[me].Area() > 0))
      c.Near("box inside the image", 1, 0);
    c.Near("before", 1, r.before);  // a segmented person is dynamic (Sec. 3.1)
    c.Near("after", 1, r.after);
    CheckFrameAreas(t, b, prev, at.frame_pos, c);
  }
};

// blur.compensation on a pasted prediction r<frame>.<k>: trigger, history, fit, translation.
class PasteVerifier : public BlurVerifier {
 public:
  using BlurVerifier::BlurVerifier;
  bool Claims(const Record& r) const override {
    return r.type == RecordType::kProbability && r.stage == kComp && r.kind == EntityKind::kPixelRegion;
  }
  void Verify(const TraceModel& t, RecordRef at, Check& c) const override {
    const auto& frames = index_->Of(t);
    const BlurFrame& b = frames[at.frame_pos];
    const BlurFrame* prev = Previous(frames, at.frame_pos);
    const Record& r = t.At(at);
    const double track = c.Need(r, "track"), n = c.Need(r, "samples"), t_c = c.Need(r, "t_c");
    const double history = Config(t, c, kMask, "history"), max_run = Config(t, c, kMask, "max_consecutive");
    for (const char* k : {"from_x", "from_y", "to_x", "to_y", "dx", "dy", "x_min", "y_min", "x_max", "y_max",
                          "moved_px", "pasted_px", "consecutive"})
      c.Need(r, k);
    std::vector<std::array<double, 3>> h;
    for (int64_t j = 0; c.ok() && j < int64_t(n); ++j) {
      const std::string k = std::to_string(j);
      h.push_back({c.Need(r, "x" + k), c.Need(r, "y" + k), c.Need(r, "t" + k)});
    }
    if (!c.ok()) return;
    if (!t.camera().present) return c.Missing("header camera_json");
    c.Same("triggered (r < r_threshold)", true, Triggered(t, b, c));
    c.Near("t_c", b.has_stamp ? b.stamp : NAN, t_c, 0);
    const auto state = prev ? prev->tracks.find(int64_t(track)) : std::map<int64_t, TrackState>::const_iterator();
    if (prev == nullptr || state == prev->tracks.end()) return c.Missing("track " + std::to_string(int64_t(track)) + " in the previous frame");
    c.Same("track not found by a person", false, FoundNow(t, b, at.frame_pos, int64_t(track)));
    const TrackState& s = state->second;
    c.Same("consecutive < max_consecutive", true, double(s.consecutive) < max_run);
    c.Near("in.consecutive", double(s.consecutive + 1), *Input(r, "consecutive"));
    // The (x, y, t) history is the track's states in the preceding frames (newest last).
    const auto expect = History(frames, at.frame_pos - 1, int64_t(track), int64_t(history));
    c.Near("in.samples", double(expect.size()), n);
    for (size_t j = 0; c.ok() && j < expect.size() && j < h.size(); ++j)
      for (int q = 0; q < 3; ++q)
        c.Near(std::string("in.") + "xyt"[q] + std::to_string(j), expect[j][q], h[j][q], 0);
    if (!c.ok()) return;
    const auto [px, py] = FitCorner(h, t_c);
    c.Near("in.to_x", px, *Input(r, "to_x"));
    c.Near("in.to_y", py, *Input(r, "to_y"));
    c.Near("in.from_x", s.ax, *Input(r, "from_x"), 0);
    c.Near("in.from_y", s.ay, *Input(r, "from_y"), 0);
    const int64_t dx = std::lround(px - s.ax), dy = std::lround(py - s.ay);
    c.Near("in.dx", double(dx), *Input(r, "dx"), 0);
    c.Near("in.dy", double(dy), *Input(r, "dy"), 0);
    // The last mask translated by (dx, dy), clipped: its tight box is the translated box when
    // that lies in the image, else inside the clipped translated box.
    const Box moved{s.box.x0 + dx, s.box.y0 + dy, s.box.x1 + dx, s.box.y1 + dy};
    const Box image{0, 0, t.camera().width - 1, t.camera().height - 1};
    const Box clipped = moved.Meet(image), got = BoxOf(r);
    if (clipped == moved) {
      c.Near("in.x_min", double(moved.x0), double(got.x0), 0);
      c.Near("in.y_min", double(moved.y0), double(got.y0), 0);
      c.Near("in.x_max", double(moved.x1), double(got.x1), 0);
      c.Near("in.y_max", double(moved.y1), double(got.y1), 0);
    } else if (!(got.Meet(clipped) == got) || got.Area() == 0) {
      c.Near("box inside the clipped translated box", 1, 0);
    }
    const double moved_px = *Input(r, "moved_px"), pasted_px = *Input(r, "pasted_px");
    if (!(moved_px > 0 && moved_px <= double(got.Area()))) c.Near("in.moved_px in (0, box area]", 1, 0);
    if (!(pasted_px >= 0 && pasted_px <= moved_px)) c.Near("in.pasted_px in [0, moved_px]", 1, 0);
    c.Near("before", 0, r.before);  // not in the segmenter's mask
    c.Near("after", 1, r.after);    // pasted into M_s: dynamic
    CheckFrameAreas(t, b, prev, at.frame_pos, c);
  }
};

// blur.compensation DECISION kept = 0 on a track's last state (previous frame): the track ends.
class TrackEndVerifier : public BlurVerifier {
 public:
  using BlurVerifier::BlurVerifier;
  bool Claims(const Record& r) const override { return r.type == RecordType::kDecision && r.stage == kComp; }
  void Verify(const TraceModel& t, RecordRef at, Check& c) const override {
    const auto& frames = index_->Of(t);
    const BlurFrame& b = frames[at.frame_pos];
    const BlurFrame* prev = Previous(frames, at.frame_pos);
    const Record& r = t.At(at);
    if (prev == nullptr) return c.Missing("blur.mask records of the previous frame");
    const auto& prev_recs = t.frames()[at.frame_pos - 1].records;
    int64_t track = -1;
    for (const auto& [id, s] : prev->tracks)
      if (prev_recs[s.rec].entity == r.entity) track = id;
    if (track < 0) return c.Missing("a previous-frame track state named " + r.entity);
    const TrackState& s = prev->tracks.at(track);
    c.Same("kept", false, r.kept);
    c.Same("track found by a person", false, FoundNow(t, b, at.frame_pos, track));
    for (size_t i : b.pastes)
      if (Input(t.frames()[at.frame_pos].records[i], "track").value_or(-1) == double(track))
        c.Same("track pasted", false, true);
    std::string why;
    if (Config(t, c, kMask, "compensation") == 0) why = "lost:compensation-off";
    else if (!Triggered(t, b, c)) why = "lost:not-triggered";
    else if (double(s.consecutive) >= Config(t, c, kMask, "max_consecutive")) why = "lost:max-consecutive";
    else why = "lost:outside-image";
    if (!c.ok()) return;
    c.Same("reason", why, r.reason);
    if (why != "lost:outside-image") return;
    // Predicted out of the image: the translated box cannot lie inside it.
    if (!t.camera().present || !b.has_stamp) return c.Missing("header camera_json / frame stamp");
    const auto h = History(frames, at.frame_pos - 1, track, int64_t(Config(t, c, kMask, "history")));
    const auto [px, py] = FitCorner(h, b.stamp);
    const int64_t dx = std::lround(px - double(s.box.x0)), dy = std::lround(py - double(s.box.y0));
    const Box moved{s.box.x0 + dx, s.box.y0 + dy, s.box.x1 + dx, s.box.y1 + dy};
    const Box image{0, 0, t.camera().width - 1, t.camera().height - 1};
    if (moved.Meet(image) == moved) c.Same("predicted box leaves the image", true, false);
  }
};

// blur.depth_fusion on a person box r<frame>.<k>: samples, human value range, 3-sigma screen.
class DepthVerifier : public BlurVerifier {
 public:
  using BlurVerifier::BlurVerifier;
  bool Claims(const Record& r) const override { return r.type == RecordType::kProbability && r.stage == kDepth; }
  void Verify(const TraceModel& t, RecordRef at, Check& c) const override {
    const auto& frames = index_->Of(t);
    const BlurFrame& b = frames[at.frame_pos];
    const Record& r = t.At(at);
    const auto& recs = t.frames()[at.frame_pos].records;
    const double alpha = Config(t, c, kMask, "alpha_m"), k = Config(t, c, kMask, "sigma_mult");
    c.Same("config blur.mask.depth_fusion", true, Config(t, c, kMask, "depth_fusion") != 0);
    for (const char* n : {"box", "x_min", "y_min", "x_max", "y_max", "in_box", "samples", "g_h", "lo", "hi",
                          "mu_box", "sigma_box", "box_valid_px", "fused_px", "added_px"})
      c.Need(r, n);
    if (!c.ok()) return;
    const double samples = *Input(r, "samples");
    std::vector<double> d;
    for (int64_t j = 0; c.ok() && j < int64_t(samples); ++j) d.push_back(c.Need(r, "d" + std::to_string(j)));
    if (!b.samples_known) c.Missing("config blur.mask sampling keys / header camera_json");
    if (!c.ok()) return;
    // The fused boxes are the compensation's boxes: persons, then pastes, in record order.
    std::vector<size_t> regions = b.persons;
    regions.insert(regions.end(), b.pastes.begin(), b.pastes.end());
    const size_t bi = size_t(*Input(r, "box"));
    if (bi >= regions.size()) return c.Near("in.box (a compensation box)", double(regions.size()), double(bi));
    const Box box = BoxOf(recs[regions[bi]]), got = BoxOf(r);
    c.Same("box = compensation box " + std::to_string(bi), true, box == got);
    int64_t in_box = 0;
    for (const auto& [x, y] : b.samples) in_box += x >= box.x0 && x <= box.x1 && y >= box.y0 && y <= box.y1;
    c.Near("in.in_box", double(in_box), *Input(r, "in_box"), 0);
    if (samples > double(in_box)) c.Near("in.samples <= in_box", double(in_box), samples, 0);
    const double fused = *Input(r, "fused_px"), valid = *Input(r, "box_valid_px");
    if (samples == 0) {
      for (const char* n : {"g_h", "lo", "hi", "fused_px"}) c.Near(std::string("in.") + n, 0, *Input(r, n), 0);
    } else {
      // g_h = (1/n) sum g(p) over the valid samples in the box; O_h = [g_h - alpha, g_h + alpha].
      double sum = 0;
      for (double g : d) {
        if (!(g > 0)) c.Near("sample depth > 0", 1, 0);
        sum += g;
      }
      const double g_h = sum / samples;
      c.Near("in.g_h", g_h, *Input(r, "g_h"));
      c.Near("in.lo", g_h - alpha, *Input(r, "lo"));
      c.Near("in.hi", g_h + alpha, *Input(r, "hi"));
      if (!(valid >= samples && valid <= double(box.Area()))) c.Near("in.box_valid_px in [samples, box area]", 1, 0);
      if (!(fused >= 0 && fused <= valid)) c.Near("in.fused_px in [0, box_valid_px]", 1, 0);
      // M_d: g in O_h and |g - mu_B| <= k sigma_B; an empty intersection fuses nothing.
      const double mu = *Input(r, "mu_box"), sd = *Input(r, "sigma_box");
      if (std::max(*Input(r, "lo"), mu - k * sd) > std::min(*Input(r, "hi"), mu + k * sd))
        c.Near("in.fused_px (O_h misses the 3-sigma band)", 0, fused, 0);
      if (!(sd >= 0)) c.Near("in.sigma_box >= 0", 1, 0);
    }
    const double added = *Input(r, "added_px");
    if (!(added >= 0 && added <= fused)) c.Near("in.added_px in [0, fused_px]", 1, 0);
    c.Near("before", 0, r.before);
    c.Near("after", fused > 0 ? 1.0 : 0.0, r.after);  // the box's M_d^i is dynamic when non-empty
    CheckFrameAreas(t, b, Previous(frames, at.frame_pos), at.frame_pos, c);
  }
};

// blur.probability on a keypoint f<frame>.<i>: Eq. (20) and the neighbour probability (Sec. 3.3).
class KeypointVerifier : public BlurVerifier {
 public:
  using BlurVerifier::BlurVerifier;
  bool Claims(const Record& r) const override { return r.type == RecordType::kProbability && r.stage == kProb; }
  void Verify(const TraceModel& t, RecordRef at, Check& c) const override {
    const auto& frames = index_->Of(t);
    const BlurFrame& b = frames[at.frame_pos];
    const Record& r = t.At(at);
    const auto& recs = t.frames()[at.frame_pos].records;
    const double x = c.Need(r, "x"), y = c.Need(r, "y"), n_rec = c.Need(r, "neighbours");
    const double dyn_rec = c.Need(r, "dynamic_neighbours");
    const double D = Config(t, c, kProb, "radius_px"), c1 = Config(t, c, kProb, "c1"), c2 = Config(t, c, kProb, "c2");
    const double theta = Config(t, c, kProb, "theta"), compute = Config(t, c, kProb, "compute");
    const double size = Config(t, c, kMask, "dilation_size");
    c.Near("in.radius_px", D, c.Need(r, "radius_px"), 0);
    c.Near("in.theta", theta, c.Need(r, "theta"), 0);
    if (!c.ok()) return;
    // Eq. (20): P = 1 inside M_sd. M_sd is not in the trace; it lies within dilation_size of the
    // boxes of the persons and pastes (depth fusion stays inside them): a P = 1 keypoint must too.
    if (r.before != 0 && r.before != 1) return c.Near("before (Eq. (20): 0 or 1)", 1, r.before);
    if (r.before == 1) {
      const int64_t px = int64_t(float(x) + 0.5f), py = int64_t(float(y) + 0.5f);  // the pixel looked up
      bool inside = false;
      for (const auto* list : {&b.persons, &b.pastes})
        for (size_t i : *list) {
          const Box q = BoxOf(recs[i]);
          inside |= px >= q.x0 - size && px <= q.x1 + size && py >= q.y0 - size && py <= q.y1 + size;
        }
      c.Same("P = 1 keypoint within dilation_size of a person box", true, inside);
    }
    double post = r.before, n = 0, dyn = 0;
    if (compute != 0 && r.before == 0) {
      // X_i = {x_k : k != i, |x_k - x_i| < D} over every keypoint of the frame, summed in
      // ascending keypoint order: P' = (1/n) sum_k c1 exp(-c2 r_k) P(x_k), P(x_k) pre-defined.
      std::vector<size_t> near;
      const int64_t gx = int64_t(std::floor(x / D)), gy = int64_t(std::floor(y / D));
      for (int64_t ox = -1; ox <= 1; ++ox)
        for (int64_t oy = -1; oy <= 1; ++oy) {
          const auto it = b.grid.find({gx + ox, gy + oy});
          if (it != b.grid.end()) near.insert(near.end(), it->second.begin(), it->second.end());
        }
      std::sort(near.begin(), near.end());
      double sum = 0;
      for (size_t k : near) {
        if (k == at.index) continue;
        const double ex = Input(recs[k], "x").value_or(NAN) - x, ey = Input(recs[k], "y").value_or(NAN) - y;
        const double dist = std::sqrt(ex * ex + ey * ey);
        if (!(dist < D)) continue;
        ++n;
        if (recs[k].before == 0) continue;
        ++dyn;
        sum += c1 * std::exp(-c2 * dist);
      }
      post = n > 0 ? sum / n : 0.0;
    }
    c.Near("in.neighbours", n, n_rec, 0);
    c.Near("in.dynamic_neighbours", dyn, dyn_rec, 0);
    c.Near("after", post, r.after);
    // Removal (E9: P > theta is dynamic) is a DECISION kept = 0 of this stage on the keypoint.
    c.Same("removed (P > theta)", post > theta, b.removal_of.count(r.entity) > 0);
  }
};

// blur.probability DECISION kept = 0 on a removed keypoint: its probability exceeds theta.
class RemovalVerifier : public BlurVerifier {
 public:
  using BlurVerifier::BlurVerifier;
  bool Claims(const Record& r) const override { return r.type == RecordType::kDecision && r.stage == kProb; }
  void Verify(const TraceModel& t, RecordRef at, Check& c) const override {
    const BlurFrame& b = index_->Of(t)[at.frame_pos];
    const Record& r = t.At(at);
    const auto it = b.prob_of.find(r.entity);
    if (it == b.prob_of.end()) return c.Missing("blur.probability PROB of " + r.entity + " in this frame");
    const Record& p = t.frames()[at.frame_pos].records[it->second];
    const double theta = Config(t, c, kProb, "theta");
    if (!c.ok()) return;
    c.Same("kept", false, r.kept);
    c.Same("P > theta", true, p.after > theta);
    c.Same("reason", p.before > 0 ? "in-mask" : "probability>theta", r.reason);
  }
};

}  // namespace

void AddBlurVerifiers(VerifierList& out) {
  const auto index = std::make_shared<BlurIndex>();
  out.push_back(std::make_unique<PersonVerifier>(index));
  out.push_back(std::make_unique<PasteVerifier>(index));
  out.push_back(std::make_unique<TrackEndVerifier>(index));
  out.push_back(std::make_unique<DepthVerifier>(index));
  out.push_back(std::make_unique<KeypointVerifier>(index));
  out.push_back(std::make_unique<RemovalVerifier>(index));
}

}  // namespace dynref::verify
