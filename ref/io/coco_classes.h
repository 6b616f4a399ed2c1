// COCO-80 class names in darknet `coco.names` order (class id = index), spaces as underscores
// so every name is one token in dynref's text formats.
#pragma once
#include <string>

namespace dynref {

constexpr int kCocoClassCount = 80;
const char* CocoClassName(int class_id);       // "unknown" outside 0..79
int CocoClassId(const std::string& name);      // -1 if not a COCO name (accepts spaces or '_')
// Prior-dynamic classes of the papers (person + animals + vehicles that move on their own).
bool CocoIsPriorDynamic(int class_id);

}  // namespace dynref
