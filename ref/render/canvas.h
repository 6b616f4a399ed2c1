// Off-screen RGB8 drawing surface (PNGs written by OpenImageIO, render/png_encoder.h). Every primitive uses
// integer rasterisation (and integer alpha blending), so pixels are identical on every machine.
#pragma once
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace dynref::render {

struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
};

class Canvas {
 public:
  Canvas(int width, int height, Rgb background);
  static Canvas FromBgr(const cv::Mat& bgr);  // CV_8UC3 BGR (as LoadRgb returns)

  int width() const { return width_; }
  int height() const { return height_; }
  Rgb Get(int x, int y) const;
  // Pixel set / blend (alpha 0..255); outside the canvas is ignored.
  void Set(int x, int y, Rgb c);
  void Blend(int x, int y, Rgb c, int alpha);

  void FillRect(int x0, int y0, int x1, int y1, Rgb c, int alpha = 255);  // inclusive corners
  void Rect(int x0, int y0, int x1, int y1, Rgb c, int thickness = 1);
  // Bresenham line from (x0,y0) to (x1,y1) with a square brush of odd `thickness`.
  void Line(int x0, int y0, int x1, int y1, Rgb c, int thickness = 1);
  // Disc / ring centred at (cx, cy) (pixel centres); a pixel is inside if dx^2+dy^2 <= r^2.
  void Disc(int cx, int cy, int radius, Rgb c);
  void Ring(int cx, int cy, int radius, int thickness, Rgb c);
  // Built-in 8x14 bitmap font (bitmap_font.h); (x, y) = top-left; scale >= 1 repeats pixels.
  void Text(int x, int y, const std::string& text, Rgb c, int scale = 1);
  // Text on a translucent dark box (readable on any background).
  void Label(int x, int y, const std::string& text, Rgb c, int scale = 1);
  static int TextWidth(const std::string& text, int scale = 1);
  static int TextHeight(int scale = 1);
  // Copies `src` with its top-left at (x, y).
  void Paste(const Canvas& src, int x, int y);

  // Writes a PNG atomically (temp + rename). Throws std::runtime_error on failure.
  void WritePng(const std::string& path) const;

 private:
  uint8_t* Px(int x, int y) { return pixels_.data() + (static_cast<size_t>(y) * width_ + x) * 3; }
  const uint8_t* Px(int x, int y) const {
    return pixels_.data() + (static_cast<size_t>(y) * width_ + x) * 3;
  }
  int width_, height_;
  std::vector<uint8_t> pixels_;  // RGB, rows top to bottom
};

}  // namespace dynref::render
