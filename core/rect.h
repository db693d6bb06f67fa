#pragma once
// A pixel rectangle in image coordinates, shared by the LOD builder (quad
// leaves), the warp (sky rectangles) and gap filling (refreshed regions).

namespace hw {

// Pixel rectangle [x0, x1) × [y0, y1) in image coordinates (row 0 = top).
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  long long area() const { return static_cast<long long>(width()) * height(); }
};

}  // namespace hw
