#include "dynamic/epi/enhance_files.h"

#include <opencv2/imgproc.hpp>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "io/sequence.h"
#include "io/image_file.h"

namespace fs = std::filesystem;

namespace dynref::epi {
namespace {

bool IsEnhanceOutput(const std::string& dir) {
  if (IsAbsentOrEmptyDirectory(dir)) return true;
  std::ifstream in(dir + "/enhance.txt");
  std::string first;
  return in && std::getline(in, first) && first.rfind("# dynref enhance", 0) == 0;
}

void WritePng(const std::string& path, const cv::Mat& img) {
  std::vector<uchar> buf;
  if (!dynref::ImageEncode(".png", img, buf)) throw InputError(path, "cannot encode PNG");
  AtomicWriteFile(path, std::string(buf.begin(), buf.end()));
}

}  // namespace

EnhanceFilesResult EnhanceFiles(const std::string& input, const std::string& out, const EnhanceStageOptions& options) {
  struct stat st {};
  if (::stat(input.c_str(), &st) != 0) throw InputError(input, "no such image or sequence folder");
  const std::string target = StagingDirectory::NormalisedTarget(out);
  if (!IsEnhanceOutput(target)) throw InputError("--out", out + " exists and was not written by dynref enhance; refusing to overwrite");
  // Inputs: (name, grey image loader) in order.
  std::vector<std::pair<std::string, std::string>> items;  // output stem, path
  std::unique_ptr<Sequence> seq;
  if (S_ISDIR(st.st_mode)) {
    seq = std::make_unique<Sequence>(OpenSequence(input));
    for (const FrameEntry& e : seq->frames) items.emplace_back(e.rgb_stamp_text, e.rgb_path);
  } else {
    items.emplace_back(fs::path(input).stem().string(), input);
  }
  StagingDirectory staging(target);
  SequenceEnhancer enhancer(options);
  std::ostringstream log;
  log << "# dynref enhance (seed 004 Module A) of " << input << "\n";
  EnhanceFilesResult r;
  for (size_t k = 0; k < items.size(); ++k) {
    cv::Mat bgr;
    if (seq) {
      bgr = LoadRgb(*seq, seq->frames[k]);
    } else {
      bgr = dynref::ImageRead(items[k].second, cv::IMREAD_COLOR);
      if (bgr.empty()) throw InputError(items[k].second, "not a readable image");
    }
    cv::Mat grey;
    cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
    BoaResult boa;
    const EnhanceResult e = enhancer.Enhance(grey, &boa);
    const EnhanceParams& q = enhancer.params();
    if (boa.evaluations > 0)
      log << "# butterfly optimisation on the first image: " << boa.evaluations << " evaluations, best fitness "
          << FormatDouble17(boa.best_fitness) << "\n";
    if (k == 0)
      log << "# alpha " << FormatDouble17(q.alpha) << " p " << FormatDouble17(q.p) << " s " << FormatDouble17(q.s)
          << " window " << q.window << "\n# image I_lo I_hi fitness mean_in mean_out\n";
    WritePng(staging.dir() + "/" + items[k].first + ".png", e.grey8);
    log << items[k].first << ".png " << FormatDouble17(e.lo) << ' ' << FormatDouble17(e.hi) << ' '
        << FormatDouble17(e.fitness) << ' ' << FormatDouble17(e.mean_in) << ' ' << FormatDouble17(e.mean_out) << "\n";
    ++r.images;
  }
  AtomicWriteFile(staging.dir() + "/enhance.txt", log.str());
  PublishDirectory(staging.dir(), target, out, IsEnhanceOutput,
                   "exists and was not written by dynref enhance; refusing to overwrite");
  staging.Commit();
  r.alpha = enhancer.params().alpha;
  r.p = enhancer.params().p;
  return r;
}

}  // namespace dynref::epi
