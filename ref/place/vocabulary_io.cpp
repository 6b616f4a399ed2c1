// Vocabulary files: dynref's own text format and ORB-SLAM2's ORBvoc.txt (README.md "Formats").
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <locale>
#include <sstream>
#include <string_view>

#include "core/atomic_file.h"
#include "core/crc32c.h"
#include "core/error.h"
#include "core/format.h"
#include "place/vocabulary.h"

namespace dynref::place {
namespace {

constexpr std::string_view kMagic = "dynref-vocabulary";
constexpr int kFormatVersion = 1;

// Splits `text` into lines (LF, an optional CR before it dropped) and lines into tokens.
class LineReader {
 public:
  LineReader(const std::string& text, const std::string& file) : text_(text), file_(file) {}
  // Next line; false at the end. offset() is where the returned line starts.
  bool Next(std::string_view* line) {
    if (pos_ >= text_.size()) return false;
    start_ = pos_;
    size_t end = text_.find('\n', pos_);
    if (end == std::string::npos) end = text_.size();
    *line = std::string_view(text_).substr(pos_, end - pos_);
    if (!line->empty() && line->back() == '\r') line->remove_suffix(1);
    pos_ = end + 1;
    ++line_;
    return true;
  }
  int line() const { return line_; }
  size_t offset() const { return start_; }
  const std::string& file() const { return file_; }

 private:
  const std::string& text_;
  std::string file_;
  size_t pos_ = 0, start_ = 0;
  int line_ = 0;
};

std::vector<std::string_view> Tokens(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

long long ParseInt(std::string_view t, const LineReader& r, const std::string& what) {
  long long v = 0;
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || p != t.data() + t.size())
    throw InputError(r.file(), r.line(), what + " '" + std::string(t) + "' is not an integer");
  return v;
}

double ParseWeight(std::string_view t, const LineReader& r) {
  double v = 0;
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || p != t.data() + t.size())
    throw InputError(r.file(), r.line(), "weight '" + std::string(t) + "' is not a number");
  return v;
}

NodeId ParseParent(std::string_view t, const LineReader& r) {
  const long long p = ParseInt(t, r, "parent id");
  if (p < 0 || p > 0xffffffffLL) throw InputError(r.file(), r.line(), "parent id " + std::string(t) + " is out of range");
  return static_cast<NodeId>(p);
}

bool ParseLeaf(std::string_view t, const LineReader& r) {
  if (t == "0") return false;
  if (t == "1") return true;
  throw InputError(r.file(), r.line(), "leaf flag '" + std::string(t) + "' is not 0 or 1");
}

int HexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

const char kHex[] = "0123456789abcdef";

std::string ReadWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open the vocabulary file");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path, "cannot read the vocabulary file");
  return ss.str();
}

}  // namespace

Vocabulary Vocabulary::ParseOrbSlamText(const std::string& text, const std::string& file) {
  // TemplatedVocabulary::loadFromTextFile (ORB-SLAM2): "k L scoring weighting", then one line
  // per node in id order: parent id, leaf flag, the 32 descriptor bytes in decimal, the weight.
  LineReader r(text, file);
  std::string_view line;
  if (!r.Next(&line)) throw InputError(file, 1, "empty vocabulary file");
  RejectUtf8Bom(file, std::string(line.substr(0, 3)));
  const auto head = Tokens(line);
  if (head.size() != 4)
    throw InputError(file, 1, "the first line must be 'k L scoring weighting' (4 integers), got " +
                                  std::to_string(head.size()) + " fields");
  const long long k = ParseInt(head[0], r, "k"), levels = ParseInt(head[1], r, "L");
  const long long scoring = ParseInt(head[2], r, "scoring type"), weighting = ParseInt(head[3], r, "weighting type");
  if (scoring < 0 || scoring > 5) throw InputError(file, 1, "scoring type " + std::to_string(scoring) + " is outside 0..5");
  if (weighting < 0 || weighting > 3)
    throw InputError(file, 1, "weighting type " + std::to_string(weighting) + " is outside 0..3");
  if (k < 2 || k > 20 || levels < 1 || levels > 10)
    throw InputError(file, 1, "k = " + std::to_string(k) + ", L = " + std::to_string(levels) +
                                  " are outside DBoW2's range (k 2..20, L 1..10)");
  std::vector<NodeRecord> nodes;
  while (r.Next(&line)) {
    const auto t = Tokens(line);
    if (t.empty()) continue;  // DBoW2 would turn a blank (e.g. the final) line into a bogus node
    if (t.size() != 3 + kDescriptorBytes)
      throw InputError(file, r.line(), "a node line has " + std::to_string(3 + kDescriptorBytes) +
                                           " fields (parent, leaf, 32 bytes, weight), got " + std::to_string(t.size()));
    NodeRecord n;
    n.line = r.line();
    n.parent = ParseParent(t[0], r);
    n.leaf = ParseLeaf(t[1], r);
    for (int b = 0; b < kDescriptorBytes; ++b) {
      const long long v = ParseInt(t[2 + b], r, "descriptor byte");
      if (v < 0 || v > 255)
        throw InputError(file, r.line(), "descriptor byte " + std::to_string(b) + " = " + std::to_string(v) +
                                             " is outside 0..255");
      n.descriptor[b] = static_cast<uint8_t>(v);
    }
    n.weight = ParseWeight(t[2 + kDescriptorBytes], r);
    nodes.push_back(n);
  }
  return FromNodes(static_cast<int>(k), static_cast<int>(levels), static_cast<Weighting>(weighting),
                   static_cast<Scoring>(scoring), nodes, file);
}

Vocabulary Vocabulary::ParseDynref(const std::string& text, const std::string& file) {
  LineReader r(text, file);
  std::string_view line;
  if (!r.Next(&line)) throw InputError(file, 1, "empty vocabulary file");
  const auto magic = Tokens(line);
  if (magic.size() != 2 || magic[0] != kMagic)
    throw InputError(file, 1, "the first line must be '" + std::string(kMagic) + " <version>'");
  if (ParseInt(magic[1], r, "format version") != kFormatVersion)
    throw InputError(file, 1, "format version " + std::string(magic[1]) + " is not supported (this dynref reads " +
                                  std::to_string(kFormatVersion) + ")");
  if (!r.Next(&line)) throw InputError(file, 2, "missing header line");
  const auto h = Tokens(line);
  const char* const keys[] = {"k", "levels", "weighting", "scoring", "descriptor", "nodes"};
  if (h.size() != 12) throw InputError(file, 2, "the header line has 12 fields: k K levels L weighting W scoring S descriptor orb256 nodes N");
  for (int i = 0; i < 6; ++i)
    if (h[2 * i] != keys[i])
      throw InputError(file, 2, "header field " + std::to_string(2 * i + 1) + " must be '" + keys[i] + "', got '" +
                                    std::string(h[2 * i]) + "'");
  const long long k = ParseInt(h[1], r, "k"), levels = ParseInt(h[3], r, "levels");
  Weighting weighting;
  Scoring scoring;
  if (!ParseWeighting(std::string(h[5]), &weighting))
    throw InputError(file, 2, "unknown weighting '" + std::string(h[5]) + "' (tf-idf, tf, idf, binary)");
  if (!ParseScoring(std::string(h[7]), &scoring))
    throw InputError(file, 2, "unknown scoring '" + std::string(h[7]) + "' (l1, l2, chi-square, kl, bhattacharyya, dot-product)");
  if (h[9] != "orb256") throw InputError(file, 2, "descriptor '" + std::string(h[9]) + "' is not supported (orb256)");
  const long long count = ParseInt(h[11], r, "node count");
  if (count < 1 || count > 100000000) throw InputError(file, 2, "node count " + std::to_string(count) + " is out of range");
  if (k < 2 || k > 20 || levels < 1 || levels > 10)
    throw InputError(file, 2, "k = " + std::to_string(k) + ", levels = " + std::to_string(levels) +
                                  " are outside DBoW2's range (k 2..20, L 1..10)");
  std::vector<NodeRecord> nodes;
  nodes.reserve(static_cast<size_t>(count));
  bool ended = false;
  while (r.Next(&line)) {
    const auto t = Tokens(line);
    if (!t.empty() && t[0] == "end") {
      if (t.size() != 3 || t[1] != "crc32c" || t[2].size() != 8)
        throw InputError(file, r.line(), "the last line must be 'end crc32c <8 hex digits>'");
      char buf[9];
      std::snprintf(buf, sizeof(buf), "%08x", Crc32c(text.data(), r.offset()));
      if (t[2] != buf)
        throw InputError(file, r.line(), "checksum " + std::string(t[2]) + " does not match the content (" + buf +
                                             "): the file was changed or damaged");
      if (static_cast<long long>(nodes.size()) != count)
        throw InputError(file, r.line(), "the header announces " + std::to_string(count) + " nodes, the file has " +
                                             std::to_string(nodes.size()));
      ended = true;
      break;
    }
    if (t.size() != 4)
      throw InputError(file, r.line(), "a node line has 4 fields (parent, leaf, 64 hex digits, weight), got " +
                                           std::to_string(t.size()));
    NodeRecord n;
    n.line = r.line();
    n.parent = ParseParent(t[0], r);
    n.leaf = ParseLeaf(t[1], r);
    if (t[2].size() != 2 * kDescriptorBytes)
      throw InputError(file, r.line(), "the descriptor must be 64 lower-case hex digits");
    for (int b = 0; b < kDescriptorBytes; ++b) {
      const int hi = HexDigit(t[2][2 * b]), lo = HexDigit(t[2][2 * b + 1]);
      if (hi < 0 || lo < 0) throw InputError(file, r.line(), "the descriptor must be 64 lower-case hex digits");
      n.descriptor[b] = static_cast<uint8_t>(hi * 16 + lo);
    }
    n.weight = ParseWeight(t[3], r);
    nodes.push_back(n);
  }
  if (!ended) throw InputError(file, r.line(), "missing the final 'end crc32c' line (file truncated?)");
  std::string_view rest;
  while (r.Next(&rest))
    if (!Tokens(rest).empty()) throw InputError(file, r.line(), "text after the 'end' line");
  return FromNodes(static_cast<int>(k), static_cast<int>(levels), weighting, scoring, nodes, file);
}

Vocabulary Vocabulary::LoadOrbSlamText(const std::string& path) { return ParseOrbSlamText(ReadWholeFile(path), path); }

Vocabulary Vocabulary::Load(const std::string& path) {
  const std::string text = ReadWholeFile(path);
  RejectUtf8Bom(path, text.substr(0, 3));
  if (text.compare(0, kMagic.size(), kMagic) == 0) return ParseDynref(text, path);
  return ParseOrbSlamText(text, path);
}

std::string Vocabulary::Serialize() const {
  std::string out;
  out.reserve(nodes_.size() * 96 + 128);
  out += std::string(kMagic) + " " + std::to_string(kFormatVersion) + "\n";
  out += "k " + std::to_string(k_) + " levels " + std::to_string(levels_) + " weighting " + WeightingName(weighting_) +
         " scoring " + ScoringName(scoring_) + " descriptor orb256 nodes " + std::to_string(nodes_.size() - 1) + "\n";
  for (size_t id = 1; id < nodes_.size(); ++id) {
    const VocabularyNode& n = nodes_[id];
    out += std::to_string(n.parent);
    out += n.leaf() ? " 1 " : " 0 ";
    for (uint8_t b : n.descriptor) {
      out += kHex[b >> 4];
      out += kHex[b & 15];
    }
    out += ' ';
    out += FormatDouble17(n.weight);
    out += '\n';
  }
  char buf[32];
  std::snprintf(buf, sizeof(buf), "end crc32c %08x\n", Crc32c(out));
  return out + buf;
}

std::string Vocabulary::SerializeOrbSlamText() const {
  // TemplatedVocabulary::saveToTextFile, byte for byte (default stream precision: 6 digits).
  std::ostringstream f;
  f.imbue(std::locale::classic());
  f << k_ << " " << levels_ << " " << " " << static_cast<int>(scoring_) << " " << static_cast<int>(weighting_) << "\n";
  for (size_t id = 1; id < nodes_.size(); ++id) {
    const VocabularyNode& n = nodes_[id];
    f << n.parent << " " << (n.leaf() ? 1 : 0) << " ";
    for (uint8_t b : n.descriptor) f << static_cast<int>(b) << " ";
    f << " " << n.weight << "\n";
  }
  return f.str();
}

void Vocabulary::Save(const std::string& path) const { AtomicWriteFile(path, Serialize()); }

}  // namespace dynref::place
