// io/png_decode.h: the libdeflate PNG decoder gives exactly OpenCV's pixels on every filter type,
// on the real TUM frames and on dynref's own images, and hands every other PNG back to OpenCV.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <libdeflate.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "io/image_file.h"
#include "io/png_decode.h"
#include "plugins/opencv_extra_abi.h"
#include "test_support.h"

using dynref::test::ScratchDir;
using dynref::test::SourcePath;

namespace {

cv::Mat OpenCvRead(const std::string& path) { return dynref::plugins::OpenCvExtraModule().imread(path, cv::IMREAD_UNCHANGED); }

bool SameImage(const cv::Mat& a, const cv::Mat& b) {
  return a.type() == b.type() && a.size() == b.size() && cv::norm(a, b, cv::NORM_INF) == 0;
}

void Put32(std::vector<unsigned char>& out, uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<unsigned char>(v >> s));
}

void PutChunk(std::vector<unsigned char>& out, const char* type, const std::vector<unsigned char>& data) {
  Put32(out, static_cast<uint32_t>(data.size()));
  std::vector<unsigned char> body(type, type + 4);
  body.insert(body.end(), data.begin(), data.end());
  out.insert(out.end(), body.begin(), body.end());
  Put32(out, libdeflate_crc32(0, body.data(), body.size()));
}

int PaethPredictor(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return (pa <= pb && pa <= pc) ? a : (pb <= pc ? b : c);
}

// A PNG written by hand: row y uses filter type y % 5, so every filter of PNG section 9 occurs,
// split over two IDAT chunks. `samples` are the rows' bytes as PNG stores them (RGB / big-endian).
struct HandPng {
  int width = 0, height = 0, bit_depth = 8, colour_type = 2, interlace = 0;
  std::vector<unsigned char> samples;
  std::vector<std::pair<std::string, std::vector<unsigned char>>> extra_chunks;  // before IDAT

  std::vector<unsigned char> Encode() const {
    const size_t bpp = (colour_type == 2 ? 3 : 1) * (bit_depth / 8);
    const size_t row = bpp * width;
    std::vector<unsigned char> filtered;
    for (int y = 0; y < height; ++y) {
      const int f = y % 5;
      filtered.push_back(static_cast<unsigned char>(f));
      for (size_t i = 0; i < row; ++i) {
        const int x = samples[y * row + i];
        const int a = i >= bpp ? samples[y * row + i - bpp] : 0;
        const int b = y > 0 ? samples[(y - 1) * row + i] : 0;
        const int c = (y > 0 && i >= bpp) ? samples[(y - 1) * row + i - bpp] : 0;
        const int pred = f == 0 ? 0 : f == 1 ? a : f == 2 ? b : f == 3 ? (a + b) / 2 : PaethPredictor(a, b, c);
        filtered.push_back(static_cast<unsigned char>(x - pred));
      }
    }
    libdeflate_compressor* c = libdeflate_alloc_compressor(6);
    std::vector<unsigned char> z(libdeflate_zlib_compress_bound(c, filtered.size()));
    z.resize(libdeflate_zlib_compress(c, filtered.data(), filtered.size(), z.data(), z.size()));
    libdeflate_free_compressor(c);
    std::vector<unsigned char> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    std::vector<unsigned char> ihdr;
    Put32(ihdr, width), Put32(ihdr, height);
    ihdr.insert(ihdr.end(), {static_cast<unsigned char>(bit_depth), static_cast<unsigned char>(colour_type), 0, 0,
                             static_cast<unsigned char>(interlace)});
    PutChunk(png, "IHDR", ihdr);
    for (const auto& [type, data] : extra_chunks) PutChunk(png, type.c_str(), data);
    const size_t half = z.size() / 2;
    PutChunk(png, "IDAT", std::vector<unsigned char>(z.begin(), z.begin() + half));
    PutChunk(png, "IDAT", std::vector<unsigned char>(z.begin() + half, z.end()));
    PutChunk(png, "IEND", {});
    return png;
  }
};

// Pseudo-random bytes with smooth parts, so that the predictors matter.
HandPng Pattern(int colour_type, int bit_depth, int w, int h) {
  HandPng p;
  p.width = w, p.height = h, p.colour_type = colour_type, p.bit_depth = bit_depth;
  const size_t n = static_cast<size_t>(w) * h * (colour_type == 2 ? 3 : 1) * (bit_depth / 8);
  uint32_t state = 12345;
  for (size_t i = 0; i < n; ++i) {
    state = state * 1664525u + 1013904223u;
    p.samples.push_back(static_cast<unsigned char>((i % 7 < 4) ? (i * 3 + (state >> 28)) : (state >> 24)));
  }
  return p;
}

std::string WriteFile(const std::string& dir, const std::string& name, const std::vector<unsigned char>& bytes) {
  const std::string path = dir + "/" + name;
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  return path;
}

}  // namespace

TEST_CASE("png decode: every PNG filter type gives OpenCV's pixels for 8-bit RGB, 16-bit and 8-bit grey", "[io]") {
  const std::string dir = ScratchDir("png_decode_filters");
  for (const auto& [colour_type, bit_depth] : std::vector<std::pair<int, int>>{{2, 8}, {0, 16}, {0, 8}}) {
    const std::string path = WriteFile(dir, "p.png", Pattern(colour_type, bit_depth, 37, 23).Encode());
    cv::Mat fast;
    INFO("colour type " << colour_type << ", " << bit_depth << " bits");
    REQUIRE(dynref::ReadPngFast(path, &fast));
    const cv::Mat reference = OpenCvRead(path);
    REQUIRE(!reference.empty());
    CHECK(SameImage(fast, reference));
    CHECK(SameImage(dynref::ImageRead(path, cv::IMREAD_UNCHANGED), reference));
  }
}

TEST_CASE("png decode: the real TUM frames and dynref's own encodings decode to OpenCV's pixels", "[io]") {
  int files = 0;
  for (const char* seq : {"datasets/real/tum_fr1_desk_9frames", "datasets/real/tum_fr3_walking_halfsphere_3frames"})
    for (const char* sub : {"rgb", "depth"}) {
      const std::filesystem::path d = SourcePath(std::string(seq) + "/" + sub);
      if (!std::filesystem::exists(d)) continue;
      for (const auto& e : std::filesystem::directory_iterator(d)) {
        if (e.path().extension() != ".png") continue;
        cv::Mat fast;
        INFO(e.path().string());
        REQUIRE(dynref::ReadPngFast(e.path().string(), &fast));
        CHECK(SameImage(fast, OpenCvRead(e.path().string())));
        ++files;
      }
    }
  CHECK(files >= 20);  // 9 + 9 desk, 3 (+ depth) walking
  // OpenCV's encoder at every compression level (the filters libpng picks per row).
  const std::string dir = ScratchDir("png_decode_opencv");
  cv::Mat rgb(48, 64, CV_8UC3), depth(48, 64, CV_16UC1);
  cv::randu(rgb, 0, 255), cv::randu(depth, 0, 65535);
  cv::GaussianBlur(rgb, rgb, cv::Size(5, 5), 0);
  for (int level = 0; level <= 9; level += 3)
    for (const cv::Mat& m : {rgb, depth}) {
      const std::string path = dir + "/l" + std::to_string(level) + ".png";
      REQUIRE(dynref::ImageWrite(path, m, {cv::IMWRITE_PNG_COMPRESSION, level}));
      cv::Mat fast;
      REQUIRE(dynref::ReadPngFast(path, &fast));
      CHECK(SameImage(fast, m));
    }
}

TEST_CASE("png decode: other kinds and damaged files go to OpenCV unchanged", "[io]") {
  const std::string dir = ScratchDir("png_decode_others");
  cv::Mat fast;
  cv::Mat bgra(8, 8, CV_8UC4, cv::Scalar(1, 2, 3, 4)), rgb16(8, 8, CV_16UC3, cv::Scalar(1, 2, 3));
  for (const auto& [name, m] : std::vector<std::pair<std::string, cv::Mat>>{{"bgra.png", bgra}, {"rgb16.png", rgb16}}) {
    const std::string path = dir + "/" + name;
    REQUIRE(dynref::ImageWrite(path, m));
    CHECK_FALSE(dynref::ReadPngFast(path, &fast));
    CHECK(SameImage(dynref::ImageRead(path, cv::IMREAD_UNCHANGED), m));  // OpenCV's own result
  }
  const std::vector<unsigned char> good = Pattern(2, 8, 16, 10).Encode();
  REQUIRE(dynref::DecodePngFast(good, &fast));
  HandPng interlaced = Pattern(2, 8, 16, 10);
  interlaced.interlace = 1;
  CHECK_FALSE(dynref::DecodePngFast(interlaced.Encode(), &fast));
  HandPng transparent = Pattern(2, 8, 16, 10);
  transparent.extra_chunks.push_back({"tRNS", {0, 1, 0, 2, 0, 3}});  // imread gives BGRA then
  const std::string trns = WriteFile(dir, "trns.png", transparent.Encode());
  CHECK_FALSE(dynref::ReadPngFast(trns, &fast));
  CHECK(dynref::ImageRead(trns, cv::IMREAD_UNCHANGED).channels() == OpenCvRead(trns).channels());
  std::vector<unsigned char> bad_crc = good;
  bad_crc[40] ^= 0x01;  // inside the first IDAT
  CHECK_FALSE(dynref::DecodePngFast(bad_crc, &fast));
  CHECK_FALSE(dynref::DecodePngFast(std::vector<unsigned char>(good.begin(), good.end() - 20), &fast));  // no IEND
  CHECK_FALSE(dynref::DecodePngFast(std::vector<unsigned char>(good.begin(), good.begin() + 7), &fast));
  std::vector<unsigned char> raw = {7, 1, 2, 3, 4, 0, 1, 2, 3, 4, 0, 1, 2, 3, 4};  // filter type 7 does not exist
  libdeflate_compressor* c = libdeflate_alloc_compressor(1);
  std::vector<unsigned char> z(libdeflate_zlib_compress_bound(c, raw.size()));
  z.resize(libdeflate_zlib_compress(c, raw.data(), raw.size(), z.data(), z.size()));
  libdeflate_free_compressor(c);
  std::vector<unsigned char> png(good.begin(), good.begin() + 8);
  std::vector<unsigned char> ihdr = {0, 0, 0, 4, 0, 0, 0, 3, 8, 0, 0, 0, 0};
  PutChunk(png, "IHDR", ihdr), PutChunk(png, "IDAT", z), PutChunk(png, "IEND", {});
  CHECK_FALSE(dynref::DecodePngFast(png, &fast));
  raw[0] = 0;  // the same file with a valid filter decodes
  c = libdeflate_alloc_compressor(1);
  z.assign(libdeflate_zlib_compress_bound(c, raw.size()), 0);
  z.resize(libdeflate_zlib_compress(c, raw.data(), raw.size(), z.data(), z.size()));
  libdeflate_free_compressor(c);
  png.assign(good.begin(), good.begin() + 8);
  PutChunk(png, "IHDR", ihdr), PutChunk(png, "IDAT", z), PutChunk(png, "IEND", {});
  REQUIRE(dynref::DecodePngFast(png, &fast));
  CHECK(fast.at<unsigned char>(0, 3) == 4);
  CHECK(fast.at<unsigned char>(2, 0) == 1);  // row 2, filter 0
}
