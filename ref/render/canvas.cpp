#include "render/canvas.h"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include "core/atomic_file.h"
#include "render/bitmap_font.h"
#include "render/png_encoder.h"

namespace dynref::render {

Canvas::Canvas(int width, int height, Rgb background)
    : width_(width), height_(height),
      pixels_(static_cast<size_t>(std::max(width, 0)) * std::max(height, 0) * 3) {
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) Set(x, y, background);
}

Canvas Canvas::FromBgr(const cv::Mat& bgr) {
  if (bgr.type() != CV_8UC3) throw std::runtime_error("canvas: expected CV_8UC3 BGR image");
  Canvas c(bgr.cols, bgr.rows, Rgb{});
  for (int y = 0; y < bgr.rows; ++y) {
    const cv::Vec3b* row = bgr.ptr<cv::Vec3b>(y);
    for (int x = 0; x < bgr.cols; ++x) c.Set(x, y, Rgb{row[x][2], row[x][1], row[x][0]});
  }
  return c;
}

Rgb Canvas::Get(int x, int y) const {
  const uint8_t* p = Px(x, y);
  return Rgb{p[0], p[1], p[2]};
}

void Canvas::Set(int x, int y, Rgb c) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  uint8_t* p = Px(x, y);
  p[0] = c.r, p[1] = c.g, p[2] = c.b;
}

void Canvas::Blend(int x, int y, Rgb c, int alpha) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  uint8_t* p = Px(x, y);
  auto mix = [alpha](int dst, int src) {
    return static_cast<uint8_t>((src * alpha + dst * (255 - alpha) + 127) / 255);
  };
  p[0] = mix(p[0], c.r), p[1] = mix(p[1], c.g), p[2] = mix(p[2], c.b);
}

void Canvas::FillRect(int x0, int y0, int x1, int y1, Rgb c, int alpha) {
  if (x0 > x1) std::swap(x0, x1);
  if (y0 > y1) std::swap(y0, y1);
  x0 = std::max(x0, 0), y0 = std::max(y0, 0);
  x1 = std::min(x1, width_ - 1), y1 = std::min(y1, height_ - 1);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) alpha >= 255 ? Set(x, y, c) : Blend(x, y, c, alpha);
}

void Canvas::Rect(int x0, int y0, int x1, int y1, Rgb c, int thickness) {
  if (x0 > x1) std::swap(x0, x1);
  if (y0 > y1) std::swap(y0, y1);
  for (int t = 0; t < thickness; ++t) {
    FillRect(x0 + t, y0 + t, x1 - t, y0 + t, c);
    FillRect(x0 + t, y1 - t, x1 - t, y1 - t, c);
    FillRect(x0 + t, y0 + t, x0 + t, y1 - t, c);
    FillRect(x1 - t, y0 + t, x1 - t, y1 - t, c);
  }
}

void Canvas::Line(int x0, int y0, int x1, int y1, Rgb c, int thickness) {
  const int h = thickness / 2;
  const int dx = std::abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
  const int dy = -std::abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
  int err = dx + dy;
  for (;;) {
    FillRect(x0 - h, y0 - h, x0 + h, y0 + h, c);
    if (x0 == x1 && y0 == y1) break;
    const int e2 = 2 * err;
    if (e2 >= dy) err += dy, x0 += sx;
    if (e2 <= dx) err += dx, y0 += sy;
  }
}

void Canvas::Disc(int cx, int cy, int radius, Rgb c) {
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx)
      if (dx * dx + dy * dy <= radius * radius) Set(cx + dx, cy + dy, c);
}

void Canvas::Ring(int cx, int cy, int radius, int thickness, Rgb c) {
  const int inner = std::max(radius - thickness, 0);
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      const int d2 = dx * dx + dy * dy;
      if (d2 <= radius * radius && d2 > inner * inner) Set(cx + dx, cy + dy, c);
    }
}

void Canvas::Text(int x, int y, const std::string& text, Rgb c, int scale) {
  int pen = x;
  for (char ch : text) {
    const uint8_t* rows = GlyphRows(ch);
    for (int r = 0; r < kGlyphHeight; ++r)
      for (int col = 0; col < kGlyphWidth; ++col)
        if (rows[r] & (1u << (kGlyphWidth - 1 - col)))
          FillRect(pen + col * scale, y + r * scale, pen + col * scale + scale - 1,
                   y + r * scale + scale - 1, c);
    pen += kGlyphWidth * scale;
  }
}

void Canvas::Label(int x, int y, const std::string& text, Rgb c, int scale) {
  FillRect(x - 2, y - 1, x + TextWidth(text, scale) + 1, y + TextHeight(scale), Rgb{0, 0, 0}, 170);
  Text(x, y, text, c, scale);
}

int Canvas::TextWidth(const std::string& text, int scale) {
  return static_cast<int>(text.size()) * kGlyphWidth * scale;
}
int Canvas::TextHeight(int scale) { return kGlyphHeight * scale; }

void Canvas::Paste(const Canvas& src, int x, int y) {
  for (int sy = 0; sy < src.height(); ++sy)
    for (int sx = 0; sx < src.width(); ++sx) Set(x + sx, y + sy, src.Get(sx, sy));
}

void Canvas::WritePng(const std::string& path) const {
  // Encoded in memory, then written through AtomicWriteFile, which checks the flush and close:
  // OIIO's file writer returned success on a full disk and left truncated PNGs (issue 20 item 1).
  AtomicWriteFile(path, EncodePngRgb8(pixels_.data(), width_, height_, path));
}

}  // namespace dynref::render
