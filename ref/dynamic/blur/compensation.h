// seed 003 Sec. 3.1, missed-segmentation compensation. When the person-mask area drops below
// r_threshold of the previous frame's (compensated) area, every person of the previous frame not
// found in the current one is predicted by a least-squares line through its box top-left corner
// over the last n frames (against time) and its last mask is pasted at the prediction.
#pragma once
#include <deque>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace dynref::blur {

struct CornerSample {
  double x = 0, y = 0;  // box top-left corner, pixels
  double t = 0;         // frame timestamp, seconds (raw Unix time is fine: centred below)
};

// Least-squares line x(t), y(t) through the samples, evaluated at t_c (spec 003 step 2). Time is
// centred, tau = t - t_c, so that raw Unix timestamps (~1.3e9 s) do not cancel catastrophically
// in n*sum(tau^2) - sum(tau)^2; the prediction is then the intercepts (b1, b2). With 2 samples this
// is the line through them, with 1 the sample itself; 0 samples or equal times: the last sample.
cv::Point2d PredictCorner(const std::vector<CornerSample>& history, double t_c);

struct CompensationOptions {
  double r_threshold = 0.9;   // paper Sec. 3.1
  int history = 3;            // n, paper Sec. 3.1
  double iou_found = 0.3;     // association "local template matching" (E3): box IoU >= this = found
  int max_consecutive = 5;    // not stated: a track is predicted at most this many frames in a row
  void Check() const;         // std::invalid_argument naming the field
};

// One person of the current frame as the segmenter gave it.
struct PersonMask {
  int detection_id = 0;  // id in the detections file
  cv::Mat mask;          // CV_8U 0/255, full image
  cv::Rect box;          // tight box of mask
};

struct PastedMask {
  int track = 0;                  // track id (stable across frames)
  int samples = 0;                // history entries used for the fit
  std::vector<CornerSample> history;  // the (x, y, t) the fit used, oldest first (trace)
  cv::Point2d from, to;           // the last mask's corner (its anchor) and the predicted corner
  cv::Point shift;                // (dx, dy) = round(to - from): the translation of the last mask
  cv::Rect box;                   // tight box of the translated, clipped mask
  int moved_px = 0;               // pixels of the translated, clipped mask
  int pasted_px = 0;              // pixels the paste added to M_s (not already in it)
  int consecutive = 0;            // frames in a row this track has been predicted, this one included
};

// How a current person was associated (E3), in the order of the persons given to Process.
struct PersonAssociation {
  int track = 0;                  // track id (a new one when not found)
  bool found = false;             // matched to a previous track (box IoU >= iou_found)
  double iou = 0;                 // box IoU with that track's last box (0 when new)
};

// A previous track neither found nor pasted in this frame: it ends here.
struct DroppedTrack {
  enum Why { kCompensationOff, kNotTriggered, kMaxConsecutive, kOutsideImage };
  int track = 0;
  Why why = kNotTriggered;
};

struct CompensationResult {
  cv::Mat mask;                   // M_s after compensation, CV_8U 0/255
  cv::Mat compensated;            // CV_8U 255 where the pastes added pixels
  std::vector<cv::Rect> boxes;    // person boxes after compensation (detected then pasted)
  double area_now = 0, area_before = 0;
  double r = -1;                  // A_c / A_{c-1}; -1 when A_{c-1} = 0 (no compensation, E1)
  bool triggered = false;         // r < r_threshold
  std::vector<PastedMask> pasted;
  std::vector<PersonAssociation> association;  // one per current person
  std::vector<DroppedTrack> dropped;           // ascending track id
};

// Keeps the per-person history across frames (one instance per run).
class MissedSegmentationCompensator {
 public:
  MissedSegmentationCompensator(const CompensationOptions& options, cv::Size image_size);
  // Current frame's persons (ascending detection id) at time t; enabled = false only tracks
  // (the "w/o compensation" ablation keeps M_s from the network).
  CompensationResult Process(double t, const std::vector<PersonMask>& persons, bool enabled = true);

 private:
  struct Track {
    int id = 0;
    std::deque<CornerSample> history;  // newest last, at most options.history entries
    cv::Mat mask;                      // last (possibly pasted) mask
    cv::Rect box;
    // Where the last mask's box corner sits unclipped: a person's box corner; after a paste the
    // previous anchor + (dx, dy). A paste clipped at the image edge has a box that starts at
    // the edge, so translating from the box would add the clipped part (issue 38).
    cv::Point anchor;
    int consecutive = 0;               // frames in a row this track was predicted
  };
  // Steps of Process: association (E3), this frame's persons as tracks, pasting the missed ones.
  std::vector<int> Associate(const std::vector<PersonMask>& persons, std::vector<bool>* track_found) const;
  void ContinueTracks(double t, const std::vector<PersonMask>& persons, const std::vector<int>& track_of_person,
                      CompensationResult* res, std::vector<Track>* next);
  void PasteMissed(double t, const std::vector<bool>& track_found, CompensationResult* res,
                   std::vector<Track>* next) const;
  CompensationOptions o_;
  cv::Size size_;
  std::vector<Track> tracks_;          // the previous frame's persons, ascending id
  double last_area_ = 0;
  int next_id_ = 1;
};

double BoxIou(const cv::Rect& a, const cv::Rect& b);

}  // namespace dynref::blur
