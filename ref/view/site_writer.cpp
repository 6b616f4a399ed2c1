#include "view/site_writer.h"

#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "render/overlay.h"
#include "trace/trace_diff.h"
#include "view/site_assets.h"
#include "view/site_data.h"
#include "io/image_file.h"

namespace dynref::view {
namespace {

namespace fs = std::filesystem;
constexpr const char* kMarker = ".dynref-view";  // marks a folder written by dynref view

// Overlays of every traced frame as OUT/img/r<k>_<frame>.jpg; frame -> relative path.
std::map<int64_t, std::string> RenderImages(const std::string& run, int k, const std::string& out_dir,
                                            const ViewOptions& options) {
  std::map<int64_t, std::string> images;
  const render::RunInfo info = render::ReadRunInfo(run);
  if (info.sequence.empty() || !fs::exists(info.sequence)) return images;
  trace::TraceReader reader(info.trace_path);
  int64_t first = -1, last = -1;
  for (const auto& g : reader.groups())
    if (g.frame >= 0) first = first < 0 ? g.frame : std::min(first, g.frame), last = std::max(last, g.frame);
  if (first < 0) return images;
  render::OverlayOptions o;
  o.gt = fs::exists(info.sequence + "/gt/moving.txt");
  o.out_dir = out_dir + "/.png_r" + std::to_string(k);
  const std::vector<std::string> pngs = render::RenderRunOverlays(run, first, last, o);
  fs::create_directories(out_dir + "/img");
  const std::vector<int> params = {cv::IMWRITE_JPEG_QUALITY, options.jpeg_quality};
  for (const std::string& png : pngs) {
    // overlay_<frame:06>.png
    const std::string stem = fs::path(png).stem().string();
    const int64_t frame = std::stoll(stem.substr(stem.find('_') + 1));
    const std::string rel = "img/r" + std::to_string(k) + "_" + std::to_string(frame) + ".jpg";
    cv::Mat img = dynref::ImageRead(png, cv::IMREAD_COLOR);
    if (!img.empty() && options.image_scale != 1.0)
      cv::resize(img, img, cv::Size(), options.image_scale, options.image_scale, cv::INTER_AREA);
    if (img.empty() || !dynref::ImageWrite(out_dir + "/" + rel, img, params))
      throw InputError(out_dir + "/" + rel, "cannot write the overlay image");
    images[frame] = rel;
  }
  fs::remove_all(o.out_dir);
  return images;
}

// The first divergence of run k against run 0 (JSON text; "" when identical).
std::string FirstDivergence(const std::string& oracle, const std::string& candidate) {
  trace::DiffOptions o;
  o.max_report = 1;
  const trace::DiffResult d = trace::DiffTraces(trace::ResolveTracePath(oracle), trace::ResolveTracePath(candidate), o);
  nlohmann::json j = {{"total", d.total_divergences}};
  if (!d.divergences.empty()) {
    const trace::Divergence& v = d.divergences.front();
    j["frame"] = v.frame, j["type"] = v.type, j["stage"] = v.stage, j["entity"] = v.entity;
    j["field"] = v.field, j["expected"] = v.expected, j["actual"] = v.actual, j["text"] = v.Describe();
  }
  return j.dump();
}

// Runs of the same method are an oracle and a candidate (the first divergence means something).
bool SameMethod(const std::string& a, const std::string& b) {
  trace::TraceReader ra(trace::ResolveTracePath(a)), rb(trace::ResolveTracePath(b));
  return ra.HeaderValue("method") == rb.HeaderValue("method");
}

uint64_t FolderBytes(const std::string& dir) {
  uint64_t n = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) n += e.file_size();
  return n;
}

}  // namespace

void ViewOptions::Check() const {
  if (runs.empty()) throw InputError("RUN", "give at least one run folder");
  if (out_dir.empty()) throw InputError("--out", "required");
  if (jpeg_quality < 1 || jpeg_quality > 100) throw InputError("--jpeg-quality", "must be 1..100");
  if (!(image_scale >= 0.1 && image_scale <= 1.0)) throw InputError("--image-scale", "must be 0.1..1");
  if (digits < 1 || digits > 17) throw InputError("--digits", "must be 1..17");
  if (chunk_frames < 1 || chunk_frames > 1000) throw InputError("--chunk-frames", "must be 1..1000");
  if (threads < 1 || threads > 64) throw InputError("--threads", "must be 1..64");
  for (const std::string& r : runs)
    if (!fs::exists(trace::ResolveTracePath(r))) throw InputError(r, "no trace.dtr (run with --trace full)");
  if (fs::exists(out_dir) && !fs::is_empty(out_dir) && !fs::exists(out_dir + "/" + kMarker))
    throw InputError(out_dir, "exists and was not written by dynref view: refusing to replace it");
}

ViewResult WriteSite(const ViewOptions& options) {
  options.Check();
  const std::string tmp = options.out_dir + ".tmp." + std::to_string(::getpid());
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  ViewResult result;
  nlohmann::json runs = nlohmann::json::array();
  try {
    for (size_t k = 0; k < options.runs.size(); ++k) {
      const std::string& run = options.runs[k];
      if (options.progress) std::cerr << "view: run " << k + 1 << "/" << options.runs.size() << " " << run << "\n";
      std::map<int64_t, std::string> images;
      if (options.overlays) images = RenderImages(run, static_cast<int>(k), tmp, options);
      const std::string divergence =
          k == 0 || !SameMethod(options.runs[0], run) ? "" : FirstDivergence(options.runs[0], run);
      const DataOptions data{options.digits, options.image_scale, options.chunk_frames, options.threads};
      const RunSite site = WriteRunData(run, static_cast<int>(k), tmp, data, images, divergence);
      result.frames += static_cast<int64_t>(site.frames.size());
      result.images += static_cast<int64_t>(images.size());
      runs.push_back({{"label", site.label}, {"frames", site.frames.size()}});
    }
    for (const SiteAsset& a : SiteAssets()) AtomicWriteFile(tmp + "/" + a.name, a.content);
    AtomicWriteFile(tmp + "/data/runs.js", "VIEW.runs(" + runs.dump() + ");\n");
    AtomicWriteFile(tmp + "/" + kMarker, "written by dynref view\n");
  } catch (...) {
    fs::remove_all(tmp);
    throw;
  }
  result.bytes = FolderBytes(tmp);
  fs::remove_all(options.out_dir);
  fs::rename(tmp, options.out_dir);
  return result;
}

}  // namespace dynref::view
