// The table of backbone keys (issue 12; one source per default, issue 33): each key names the
// field(s) of BackboneOptions it reads and writes, its type, range and the source of its default.
// The default itself lives only in the option structs (backbone_options.h and the rooms below):
// a key's default text is read from BackboneOptions{}, so the struct and the table cannot
// disagree. Internal to the pipeline room (backbone_options.cpp reads and checks the values).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "pipeline/backbone_options.h"

namespace dynref {

struct BackboneKeyRow {
  enum class Kind { kInt, kDouble, kBool, kText };
  const char* key = "";
  const char* source = "";        // where the default comes from ("default: ORB-SLAM2 ...")
  Kind kind = Kind::kDouble;
  double lo = 0, hi = 0;          // kInt, kDouble: inclusive range (kInt: checked before the int conversion)
  bool lo_open = false;           // kDouble: lo excluded (e.g. scale_factor > 1)
  const char* choices = nullptr;  // kText: the allowed values separated by '|' (nullptr = any text)
  // kInt, kDouble, kBool (0 / 1): the value of the key's field(s) and its setter. A key that sets
  // several fields (mnn2_ratio: the tracker's and the mapper's) throws std::logic_error from get
  // when they differ.
  std::function<double(const BackboneOptions&)> get;
  std::function<void(BackboneOptions&, double)> set;
  // kText: the field's text and the setter, which gets the text and the config file it came
  // from (paths are relative to that file's folder).
  std::function<std::string(const BackboneOptions&)> get_text;
  std::function<void(BackboneOptions&, const std::string&, const std::string&)> set_text;
};

// Every backbone key, in name order (backbone_keys.cpp).
const std::vector<BackboneKeyRow>& BackboneKeyRows();

}  // namespace dynref
