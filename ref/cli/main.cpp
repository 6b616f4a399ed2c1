// dynref: deterministic reference implementation and validator for dynamic-scene RGB-D SLAM.
#include <dlfcn.h>
#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <string>

#include <jpeglib.h>
#include <png.h>

#include "cli/command.h"
#include "core/error.h"

// ---- Image codec messages (issue 37 item 6) ------------------------------------------------
// OpenCV's PNG and JPEG decoders leave libpng's / libjpeg's default handlers in place, which
// print "libpng error: IHDR: CRC error" or "Premature end of JPEG file" on stderr before
// dynref's own "X: cannot read image". The dynref executable interposes the two constructors
// OpenCV calls (png_create_read_struct, jpeg_std_error: the executable's definitions take
// precedence for the shared libraries) and installs handlers that keep the message instead;
// they behave as the defaults otherwise (a libpng error still long-jumps back to OpenCV). The
// kept messages are printed after everything else, as "dynref: note: ..." lines (each distinct
// text once, with a count). Handlers a caller sets itself (OpenImageIO does) are left alone.
namespace {

std::mutex g_codec_mutex;
std::map<std::string, int>& CodecMessages() {
  static std::map<std::string, int> messages;  // ordered: printed in a stable order
  return messages;
}

void KeepCodecMessage(const std::string& text) {
  std::lock_guard<std::mutex> lock(g_codec_mutex);
  ++CodecMessages()[text];
}

void PrintCodecMessages() {
  std::lock_guard<std::mutex> lock(g_codec_mutex);
  for (const auto& [text, count] : CodecMessages())
    std::cerr << "dynref: note: " << text << (count > 1 ? " (" + std::to_string(count) + " times)" : "") << "\n";
  CodecMessages().clear();
}

template <typename Fn>
Fn NextSymbol(const char* name) {
  void* f = dlsym(RTLD_NEXT, name);
  if (!f) {
    std::fprintf(stderr, "dynref: internal error: %s not found\n", name);
    std::abort();
  }
  return reinterpret_cast<Fn>(f);
}

[[noreturn]] void QuietPngError(png_structp png, png_const_charp message) {
  KeepCodecMessage(std::string("libpng error: ") + (message ? message : "?"));
  using LongJmp = void (*)(png_const_structrp, int);
  static const LongJmp long_jmp = NextSymbol<LongJmp>("png_longjmp");
  long_jmp(png, 1);  // what libpng's default handler does after printing
  std::abort();
}

void QuietPngWarning(png_structp, png_const_charp message) {
  KeepCodecMessage(std::string("libpng warning: ") + (message ? message : "?"));
}

void QuietJpegMessage(j_common_ptr cinfo) {
  char buffer[JMSG_LENGTH_MAX] = {0};
  (*cinfo->err->format_message)(cinfo, buffer);
  KeepCodecMessage(std::string("libjpeg: ") + buffer);
}

}  // namespace

extern "C" {

png_structp png_create_read_struct(png_const_charp user_png_ver, png_voidp error_ptr, png_error_ptr error_fn,
                                   png_error_ptr warn_fn) {
  using Create = png_structp (*)(png_const_charp, png_voidp, png_error_ptr, png_error_ptr);
  static const Create real = NextSymbol<Create>("png_create_read_struct");
  if (error_fn == nullptr && warn_fn == nullptr) return real(user_png_ver, error_ptr, QuietPngError, QuietPngWarning);
  return real(user_png_ver, error_ptr, error_fn, warn_fn);
}

struct jpeg_error_mgr* jpeg_std_error(struct jpeg_error_mgr* err) {
  using StdError = struct jpeg_error_mgr* (*)(struct jpeg_error_mgr*);
  static const StdError real = NextSymbol<StdError>("jpeg_std_error");
  struct jpeg_error_mgr* r = real(err);
  if (r) r->output_message = QuietJpegMessage;  // warnings and the text of fatal errors
  return r;
}

}  // extern "C"

namespace {

// A command's result reached standard output only if every write and the final flush
// succeeded (issue 37 item 5: `dynref eval ... > /dev/full` exited 0). After the command
// returns (or throws), flush std::cout and stdout and check both; a failure prints
// "dynref: error: cannot write standard output (reason)" and turns the exit code into 2.
int CheckStdout(int code) {
  // A command that flushed (and failed) itself, e.g. `trace dump`, leaves the write's errno:
  // kept as the reason only when it is one a write reports.
  const int earlier = errno;
  errno = 0;
  std::cout.flush();
  int err = errno;
  const bool cout_failed = !std::cout.good();
  if (std::fflush(stdout) != 0 && errno) err = errno;
  if (!cout_failed && !std::ferror(stdout)) return code;
  if (!err && (earlier == ENOSPC || earlier == EPIPE || earlier == EIO || earlier == EDQUOT || earlier == EFBIG ||
               earlier == EBADF))
    err = earlier;
  std::cerr << "dynref: error: cannot write standard output (" << (err ? std::strerror(err) : "write error") << ")\n";
  return dynref::kExitBadInput;
}

// Every exit of main: the stdout check, then the kept codec messages (after dynref's own).
int Finish(int code) {
  code = CheckStdout(code);
  PrintCodecMessages();
  return code;
}

// CLI11 reports an unknown word where a subcommand is required as "A subcommand is required".
// Walks the command words (before the first option) and, at the first one that is not a
// subcommand of the node reached so far, prints "unknown command" with the valid names (and,
// when the words end where a subcommand is required, the valid names too). False: leave the
// error to CLI11.
bool ReportUnknownSubcommand(CLI::App& root, int argc, char** argv) {
  CLI::App* node = &root;
  std::string path = "dynref";
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.empty() || word[0] == '-') return false;
    const auto subs = node->get_subcommands([](CLI::App*) { return true; });
    if (subs.empty()) return false;  // a leaf: positional arguments follow
    CLI::App* next = nullptr;
    std::string valid;
    for (CLI::App* s : subs) {
      if (s->check_name(word)) next = s;
      valid += (valid.empty() ? "" : ", ") + s->get_name();
    }
    if (!next) {
      std::cerr << "dynref: error: unknown command '" << word << "' for '" << path << "' (valid: " << valid
                << "; see " << path << " --help)\n";
      return true;
    }
    node = next;
    path += " " + next->get_name();
  }
  // Words ran out at a node that needs a subcommand: say which ones exist.
  const auto subs = node->get_subcommands([](CLI::App*) { return true; });
  if (subs.empty() || node->get_require_subcommand_min() == 0) return false;
  std::string valid;
  for (CLI::App* s : subs) valid += (valid.empty() ? "" : ", ") + s->get_name();
  std::cerr << "dynref: error: a subcommand is required for '" << path << "' (valid: " << valid << "; see "
            << path << " --help)\n";
  return true;
}

}  // namespace

namespace {

int RunMain(int argc, char** argv) {
  cv::setNumThreads(0);  // determinism: OpenCV runs single-threaded everywhere
  // dynref reports unreadable images itself; OpenCV's warnings ("imread_(...): can't open/read
  // file") would precede that message (issue 37 item 6). OPENCV_LOG_LEVEL still overrides.
  const char* log_level = std::getenv("OPENCV_LOG_LEVEL");
  if (!log_level || !*log_level) cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
  CLI::App root{"dynref: deterministic reference implementation and validator for dynamic-scene "
                "RGB-D SLAM"};
  root.require_subcommand(1);
  dynref::cli::CommandList commands;
  dynref::cli::RegisterAllCommands(root, commands);
  try {
    root.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() != 0 && ReportUnknownSubcommand(root, argc, argv)) return dynref::kExitBadInput;
    const int code = root.exit(e);  // prints help or the parse error
    return code == 0 ? dynref::kExitOk : dynref::kExitBadInput;
  }
  try {
    for (const auto& cmd : commands)
      if (cmd.app->parsed()) return cmd.run();
    std::cerr << "dynref: no command selected (see dynref --help)\n";
    return dynref::kExitBadInput;
  } catch (const dynref::InputError& e) {
    std::cerr << "dynref: error: " << e.what() << "\n";
    return dynref::kExitBadInput;
  } catch (const std::filesystem::filesystem_error& e) {
    // Not the library's "filesystem error: ..." text: the path and the system's reason.
    std::cerr << "dynref: error: " << (e.path1().empty() ? std::string("<filesystem>") : e.path1().string())
              << ": " << e.code().message() << "\n";
    return dynref::kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "dynref: error: " << e.what() << "\n";
    return dynref::kExitBadInput;
  }
}

}  // namespace

int main(int argc, char** argv) { return Finish(RunMain(argc, argv)); }
