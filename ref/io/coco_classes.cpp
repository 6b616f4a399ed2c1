#include "io/coco_classes.h"

#include <algorithm>

namespace dynref {
namespace {
const char* const kNames[kCocoClassCount] = {
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
}  // namespace

const char* CocoClassName(int class_id) {
  if (class_id < 0 || class_id >= kCocoClassCount) return "unknown";
  return kNames[class_id];
}

int CocoClassId(const std::string& name) {
  std::string n = name;
  std::replace(n.begin(), n.end(), ' ', '_');
  for (int i = 0; i < kCocoClassCount; ++i)
    if (n == kNames[i]) return i;
  return -1;
}

bool CocoIsPriorDynamic(int class_id) {
  // person, bicycle..boat (vehicles), bird..giraffe (animals)
  return class_id == 0 || (class_id >= 1 && class_id <= 8) || (class_id >= 14 && class_id <= 23);
}

}  // namespace dynref
