// COCO-80 class names as dynref's detection files spell them (darknet coco.names order, class id
// = index, spaces as underscores), for the verifiers that recompute a reason naming the class
// (sgdo.mask, semantic.mask). A second copy of the table on purpose: the verify room links only
// core and trace (ref/verify/README.md).
#pragma once
#include <string>

namespace dynref::verify {

inline const char* CocoName(int class_id) {
  static const char* const kNames[80] = {
      "person", "bicycle", "car", "motorbike", "aeroplane", "bus", "train", "truck", "boat",
      "traffic_light", "fire_hydrant", "stop_sign", "parking_meter", "bench", "bird", "cat", "dog",
      "horse", "sheep", "cow", "elephant", "bear", "zebra", "giraffe", "backpack", "umbrella",
      "handbag", "tie", "suitcase", "frisbee", "skis", "snowboard", "sports_ball", "kite",
      "baseball_bat", "baseball_glove", "skateboard", "surfboard", "tennis_racket", "bottle",
      "wine_glass", "cup", "fork", "knife", "spoon", "bowl", "banana", "apple", "sandwich", "orange",
      "broccoli", "carrot", "hot_dog", "pizza", "donut", "cake", "chair", "sofa", "pottedplant", "bed",
      "diningtable", "toilet", "tvmonitor", "laptop", "mouse", "remote", "keyboard", "cell_phone",
      "microwave", "oven", "toaster", "sink", "refrigerator", "book", "clock", "vase", "scissors",
      "teddy_bear", "hair_drier", "toothbrush"};
  return class_id >= 0 && class_id < 80 ? kNames[class_id] : "unknown";
}

// Class id of a config name (spaces or underscores), -1 if not a COCO name.
inline int CocoId(std::string name) {
  for (char& ch : name)
    if (ch == ' ') ch = '_';
  for (int i = 0; i < 80; ++i)
    if (name == CocoName(i)) return i;
  return -1;
}

}  // namespace dynref::verify
