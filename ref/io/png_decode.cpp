#include "io/png_decode.h"

#include <libdeflate.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <vector>

namespace dynref {
namespace {

constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

uint32_t BigEndian32(const unsigned char* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
}

struct Header {
  uint32_t width = 0, height = 0;
  int bit_depth = 0, colour_type = 0, interlace = 0;
};

// Colour type 2 (RGB) at 8 bits, or 0 (grey) at 8 or 16 bits, not interlaced: the kinds decoded
// here; everything else goes to OpenCV.
bool Supported(const Header& h) {
  const bool rgb8 = h.colour_type == 2 && h.bit_depth == 8;
  const bool grey = h.colour_type == 0 && (h.bit_depth == 8 || h.bit_depth == 16);
  return (rgb8 || grey) && h.interlace == 0 && h.width > 0 && h.height > 0 && h.width <= (1u << 16) &&
         h.height <= (1u << 16);
}

// The chunks up to IEND: the header and the concatenated IDAT data. False on a damaged file
// (bad signature, length past the end, CRC mismatch) or a chunk that changes what imread returns
// (tRNS turns RGB into BGRA; PLTE belongs to palette images).
bool ReadChunks(const std::vector<unsigned char>& b, Header* h, std::vector<unsigned char>* idat) {
  if (b.size() < 8 || std::memcmp(b.data(), kSignature, 8) != 0) return false;
  size_t pos = 8;
  bool have_header = false;
  while (pos + 12 <= b.size()) {
    const uint32_t length = BigEndian32(&b[pos]);
    if (length > b.size() - pos - 12) return false;
    const unsigned char* type = &b[pos + 4];
    const unsigned char* data = &b[pos + 8];
    const uint32_t crc = BigEndian32(data + length);
    if (libdeflate_crc32(0, type, length + 4) != crc) return false;
    if (std::memcmp(type, "IHDR", 4) == 0) {
      if (length != 13 || have_header) return false;
      h->width = BigEndian32(data);
      h->height = BigEndian32(data + 4);
      h->bit_depth = data[8], h->colour_type = data[9], h->interlace = data[12];
      if (data[10] != 0 || data[11] != 0) return false;  // compression and filter method 0
      have_header = true;
    } else if (std::memcmp(type, "IDAT", 4) == 0) {
      idat->insert(idat->end(), data, data + length);
    } else if (std::memcmp(type, "IEND", 4) == 0) {
      return have_header && !idat->empty();
    } else if (std::memcmp(type, "tRNS", 4) == 0 || std::memcmp(type, "PLTE", 4) == 0) {
      return false;
    } else if (!(type[0] & 0x20)) {
      return false;  // an unknown critical chunk
    }
    pos += 12 + length;
  }
  return false;  // no IEND
}

int Paeth(int a, int b, int c) {
  const int p = a + b - c;
  const int pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  if (pa <= pb && pa <= pc) return a;
  return pb <= pc ? b : c;
}

// PNG filter types 0-4 (PNG spec, section 9) undone in place, row by row; bpp = bytes per pixel.
bool Unfilter(unsigned char* raw, size_t rows, size_t row_bytes, size_t bpp) {
  std::vector<unsigned char> zero(row_bytes, 0);
  const unsigned char* prior = zero.data();
  for (size_t y = 0; y < rows; ++y) {
    unsigned char* line = raw + y * (row_bytes + 1);
    const int filter = line[0];
    unsigned char* x = line + 1;
    switch (filter) {
      case 0:
        break;
      case 1:
        for (size_t i = bpp; i < row_bytes; ++i) x[i] = static_cast<unsigned char>(x[i] + x[i - bpp]);
        break;
      case 2:
        for (size_t i = 0; i < row_bytes; ++i) x[i] = static_cast<unsigned char>(x[i] + prior[i]);
        break;
      case 3:
        for (size_t i = 0; i < row_bytes; ++i) {
          const int left = i >= bpp ? x[i - bpp] : 0;
          x[i] = static_cast<unsigned char>(x[i] + ((left + prior[i]) >> 1));
        }
        break;
      case 4:
        for (size_t i = 0; i < row_bytes; ++i) {
          const int left = i >= bpp ? x[i - bpp] : 0;
          const int upper_left = i >= bpp ? prior[i - bpp] : 0;
          x[i] = static_cast<unsigned char>(x[i] + Paeth(left, prior[i], upper_left));
        }
        break;
      default:
        return false;
    }
    prior = x;
  }
  return true;
}

// Unfiltered rows (each led by its filter byte) into the Mat imread would return.
void ToMat(const unsigned char* raw, const Header& h, size_t row_bytes, cv::Mat* out) {
  const int rows = static_cast<int>(h.height), cols = static_cast<int>(h.width);
  if (h.colour_type == 2) {
    cv::Mat bgr(rows, cols, CV_8UC3);
    for (int y = 0; y < rows; ++y) {
      const unsigned char* s = raw + y * (row_bytes + 1) + 1;
      unsigned char* d = bgr.ptr<unsigned char>(y);
      for (int x = 0; x < cols; ++x, s += 3, d += 3) d[0] = s[2], d[1] = s[1], d[2] = s[0];
    }
    *out = bgr;
  } else if (h.bit_depth == 16) {
    cv::Mat grey(rows, cols, CV_16UC1);
    for (int y = 0; y < rows; ++y) {
      const unsigned char* s = raw + y * (row_bytes + 1) + 1;
      uint16_t* d = grey.ptr<uint16_t>(y);
      for (int x = 0; x < cols; ++x, s += 2) d[x] = static_cast<uint16_t>((s[0] << 8) | s[1]);
    }
    *out = grey;
  } else {
    cv::Mat grey(rows, cols, CV_8UC1);
    for (int y = 0; y < rows; ++y) std::memcpy(grey.ptr<unsigned char>(y), raw + y * (row_bytes + 1) + 1, row_bytes);
    *out = grey;
  }
}

}  // namespace

bool DecodePngFast(const std::vector<unsigned char>& bytes, cv::Mat* out) {
  Header h;
  std::vector<unsigned char> idat;
  if (!ReadChunks(bytes, &h, &idat) || !Supported(h)) return false;
  const size_t channels = h.colour_type == 2 ? 3 : 1;
  const size_t bpp = channels * static_cast<size_t>(h.bit_depth / 8);
  const size_t row_bytes = bpp * h.width;
  std::vector<unsigned char> raw((row_bytes + 1) * h.height);
  std::unique_ptr<libdeflate_decompressor, decltype(&libdeflate_free_decompressor)> inflater(
      libdeflate_alloc_decompressor(), &libdeflate_free_decompressor);
  if (!inflater) return false;
  // The decompressed size must be exactly rows x (filter byte + row): LIBDEFLATE_SHORT_OUTPUT or
  // any other result sends the file to OpenCV.
  if (libdeflate_zlib_decompress(inflater.get(), idat.data(), idat.size(), raw.data(), raw.size(), nullptr) !=
      LIBDEFLATE_SUCCESS)
    return false;
  if (!Unfilter(raw.data(), h.height, row_bytes, bpp)) return false;
  ToMat(raw.data(), h, row_bytes, out);
  return true;
}

bool ReadPngFast(const std::string& path, cv::Mat* out) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return false;
  const std::streamoff size = in.tellg();
  if (size < 8) return false;
  std::vector<unsigned char> bytes(static_cast<size_t>(size));
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), size)) return false;
  return DecodePngFast(bytes, out);
}

}  // namespace dynref
