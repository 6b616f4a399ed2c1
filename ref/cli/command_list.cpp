// The one place that lists dynref's subcommands (one line per command file).
#include "cli/command.h"

#include <charconv>
#include <limits>

#include "core/error.h"

namespace dynref::cli {

void RegisterVersionCommand(CLI::App& root, CommandList& out);
void RegisterEvalCommand(CLI::App& root, CommandList& out);
void RegisterInfoCommand(CLI::App& root, CommandList& out);
void RegisterDetectCommand(CLI::App& root, CommandList& out);
void RegisterTraceCommand(CLI::App& root, CommandList& out);
void RegisterDiffCommand(CLI::App& root, CommandList& out);
void RegisterOverlayCommand(CLI::App& root, CommandList& out);
void RegisterSynthCommand(CLI::App& root, CommandList& out);

void RegisterRunCommand(CLI::App& root, CommandList& out);
void RegisterReproduceCommand(CLI::App& root, CommandList& out);
void RegisterEnhanceCommand(CLI::App& root, CommandList& out);
void RegisterMapEvalCommand(CLI::App& root, CommandList& out);
void RegisterOverviewCommand(CLI::App& root, CommandList& out);
void RegisterViewCommand(CLI::App& root, CommandList& out);
void RegisterVocabCommand(CLI::App& root, CommandList& out);

void RegisterAllCommands(CLI::App& root, CommandList& out) {
  RegisterVersionCommand(root, out);
  RegisterEvalCommand(root, out);
  RegisterMapEvalCommand(root, out);
  RegisterInfoCommand(root, out);
  RegisterDetectCommand(root, out);
  RegisterTraceCommand(root, out);
  RegisterDiffCommand(root, out);
  RegisterOverlayCommand(root, out);
  RegisterSynthCommand(root, out);
  RegisterRunCommand(root, out);
  RegisterReproduceCommand(root, out);
  RegisterOverviewCommand(root, out);
  RegisterViewCommand(root, out);
  RegisterEnhanceCommand(root, out);
  RegisterVocabCommand(root, out);
}

uint64_t ParseSeed(const std::string& text, const std::string& option) {
  uint64_t v = 0;
  const char* end = text.data() + text.size();
  const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (!digits || ec != std::errc() || ptr != end)
    throw InputError(option, "must be an integer in 0.." +
                                 std::to_string(std::numeric_limits<uint64_t>::max()) + " (got '" +
                                 text + "')");
  return v;
}

std::vector<uint64_t> ParseSeedList(const std::vector<std::string>& items, const std::string& option) {
  std::vector<uint64_t> out;
  for (const std::string& item : items) {
    const size_t dash = item.find('-');
    if (dash == std::string::npos) {
      out.push_back(ParseSeed(item, option));
      continue;
    }
    const uint64_t a = ParseSeed(item.substr(0, dash), option), b = ParseSeed(item.substr(dash + 1), option);
    if (a > b) throw InputError(option, "range '" + item + "' runs backwards");
    if (b - a >= 1000) throw InputError(option, "range '" + item + "' holds more than 1000 seeds");
    for (uint64_t s = a; s <= b; ++s) out.push_back(s);
  }
  return out;
}

}  // namespace dynref::cli
