// `dynref detect`: precomputes per-frame detections of a sequence (or one image) into dynref's
// mask format (datasets/MASK_FORMAT.md), so a run is reproducible and the network runs once.
//   dynref detect --source nanodet --sequence SEQ --out DIR [--model PATH] [--conf X] [--frames A-B]
//   dynref detect --source nanodet --image photo.jpg --overlay out.png
// Sources: ref/detect/README.md.
#include <iostream>

#include "cli/command.h"
#include "core/error.h"
#include "detect/detect_run.h"

namespace dynref::cli {
namespace {

// Options checked, frames detected and written by detect/detect_run.h; here: parse and print.
int RunDetect(const detect::DetectRunOptions& a) {
  detect::RunDetection(a, std::cout, std::cerr);
  return kExitOk;
}

}  // namespace

void RegisterDetectCommand(CLI::App& root, CommandList& out) {
  auto args = std::make_shared<detect::DetectRunOptions>();
  CLI::App* app = root.add_subcommand(
      "detect", "Precompute per-frame detections (boxes, classes, masks) into dynref's mask format");
  app->add_option("--source", args->source,
                  "nanodet | hog | onnx-yolo[:MODEL] | onnx-maskrcnn[:MODEL] | onnx-yolact[:MODEL] | files[:DIR] | labels[:DIR] | gt[:MODE]")
      ->required();
  app->add_option("--sequence", args->sequence, "TUM/Bonn/synthetic sequence folder");
  app->add_option("--image", args->image, "Single image instead of a sequence");
  app->add_option("--out", args->out, "Output dynref-detections folder");
  app->add_option("--camera", args->camera, "Camera preset or ORB-SLAM2 YAML (default: auto)");
  CLI::Option* frames = app->add_option("--frames", args->frames, "Frames A, A-B or A- (0-based, inclusive; default: all)");
  app->add_option("--input", args->input, "Folder for --source files / labels");
  app->add_option("--mode", args->mode, "Detections mode of a synthetic sequence for --source gt");
  app->add_option("--model", args->options.model_path, "Network ONNX (default: bundled models/nanodet.onnx)");
  app->add_option("--model-sha256", args->options.model_sha256, "Expected sha256 of --model");
  app->add_option("--mask-model", args->options.mask_model_path, "Selfie segmenter ONNX (default: bundled)");
  CLI::Option* conf = app->add_option("--conf", args->options.confidence_threshold,
                  "Confidence threshold in [0, 1] (default: nanodet 0.3, onnx-yolo 0.25, onnx-maskrcnn / onnx-yolact 0.05, hog 0.5)");
  app->add_option("--nms-iou", args->options.nms_iou, "Per-class NMS IoU threshold")->capture_default_str();
  app->add_option("--max-detections", args->options.max_detections, "Per frame")->capture_default_str();
  app->add_option("--input-size", args->options.yolo_input_size, "onnx-yolo / onnx-yolact square input size (the default 640 means 550 for onnx-yolact)")->capture_default_str();
  app->add_option("--class-names", args->options.class_names_file, "onnx-yolo: one class name per line");
  app->add_flag("--no-masks", args->no_masks, "Boxes only (skip selfie / YOLO-seg masks)");
  app->add_option("--temporal-gap", args->temporal.max_gap,
                  "Track persons across frames; carry a missed one this many frames as a box (0 = off; tracks.txt)")
      ->capture_default_str();
  app->add_option("--temporal-iou", args->temporal.iou_link, "Box IoU linking a detection to a track")
      ->capture_default_str();
  app->add_option("--overlay", args->overlay, "With --image: write the detections drawn on it (PNG)");
  app->add_option("--overlays", args->overlays, "With --sequence: write one overlay PNG per frame here");
  app->add_option("--repeat", args->repeat, "With --image: time N further runs (benchmark, stderr)")
      ->check(CLI::Range(0, 100000));
  out.push_back({app, [args, conf, frames] {
                   args->conf_given = conf->count() > 0;
                   args->frames_given = frames->count() > 0;
                   return RunDetect(*args);
                 }});
}

}  // namespace dynref::cli
