// A PNG decoder for the two image types of a TUM/Bonn RGB-D sequence, 8-bit RGB and 16-bit grey
// depth (and 8-bit grey), on libdeflate instead of libpng + zlib (issue 35: decoding the two PNGs
// of a frame was 17-21 ms of orb's ~70 ms per frame, zlib's inflate the largest part).
//
// The result is exactly cv::imread(path, cv::IMREAD_UNCHANGED)'s: pixels are lossless, RGB comes
// out as BGR (CV_8UC3), 16-bit grey in host order (CV_16UC1). Any other file (palette, alpha,
// tRNS, interlaced, 16-bit colour, a bad CRC, truncated data, not a PNG) returns false and the
// caller decodes it with OpenCV as before, so its errors and conversions stay OpenCV's.
#pragma once
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace dynref {

// Decodes `bytes` (a whole PNG file) into *out; false (out untouched) when it is not of the
// supported kinds above or is damaged.
bool DecodePngFast(const std::vector<unsigned char>& bytes, cv::Mat* out);

// Reads `path` and decodes it as above; false when the file cannot be read or is not supported.
bool ReadPngFast(const std::string& path, cv::Mat* out);

}  // namespace dynref
