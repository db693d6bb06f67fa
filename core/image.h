#pragma once
// Image<T>: an owning, row-major 2-D buffer; ImageView<T>: a non-owning window
// into one. Row 0 is the TOP row (PNG order); GL passes flip on readback.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/check.h"

namespace hw {

struct Rgba8 {
  std::uint8_t r = 0, g = 0, b = 0, a = 0;
  friend bool operator==(const Rgba8& x, const Rgba8& y) {
    return x.r == y.r && x.g == y.g && x.b == y.b && x.a == y.a;
  }
  friend bool operator!=(const Rgba8& x, const Rgba8& y) { return !(x == y); }
};

template <class T>
struct ImageView {
  T* data = nullptr;
  int width = 0;
  int height = 0;
  std::ptrdiff_t stride = 0;  // elements between rows

  T& operator()(int x, int y) const {
    return data[static_cast<std::ptrdiff_t>(y) * stride + x];
  }
  T& at(int x, int y) const {
    HW_CHECK(x >= 0 && x < width && y >= 0 && y < height);
    return (*this)(x, y);
  }
  T* row(int y) const { return data + static_cast<std::ptrdiff_t>(y) * stride; }
  bool empty() const { return width <= 0 || height <= 0; }
  ImageView sub(int x0, int y0, int w, int h) const {
    HW_CHECK(x0 >= 0 && y0 >= 0 && w >= 0 && h >= 0 && x0 + w <= width && y0 + h <= height);
    return ImageView{data + static_cast<std::ptrdiff_t>(y0) * stride + x0, w, h, stride};
  }
  operator ImageView<const T>() const { return ImageView<const T>{data, width, height, stride}; }
};

template <class T>
class Image {
 public:
  Image() = default;
  Image(int width, int height, const T& fill = T{}) { resize(width, height, fill); }

  void resize(int width, int height, const T& fill = T{}) {
    HW_CHECK(width >= 0 && height >= 0);
    width_ = width;
    height_ = height;
    pixels_.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), fill);
  }
  void fill(const T& v) { std::fill(pixels_.begin(), pixels_.end(), v); }

  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t size() const { return pixels_.size(); }
  bool empty() const { return pixels_.empty(); }
  T* data() { return pixels_.data(); }
  const T* data() const { return pixels_.data(); }
  std::vector<T>& pixels() { return pixels_; }
  const std::vector<T>& pixels() const { return pixels_; }

  T& operator()(int x, int y) { return pixels_[static_cast<std::size_t>(y) * width_ + x]; }
  const T& operator()(int x, int y) const {
    return pixels_[static_cast<std::size_t>(y) * width_ + x];
  }
  T& at(int x, int y) {
    HW_CHECK(x >= 0 && x < width_ && y >= 0 && y < height_);
    return (*this)(x, y);
  }
  const T& at(int x, int y) const {
    HW_CHECK(x >= 0 && x < width_ && y >= 0 && y < height_);
    return (*this)(x, y);
  }

  ImageView<T> view() { return ImageView<T>{pixels_.data(), width_, height_, width_}; }
  ImageView<const T> view() const {
    return ImageView<const T>{pixels_.data(), width_, height_, width_};
  }

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<T> pixels_;
};

}  // namespace hw
