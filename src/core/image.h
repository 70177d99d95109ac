// Images in memory: interleaved channels, row-major, pixel (0,0) at the top left
// (OpenCV convention). Image<T> owns its pixels; ImageView<T> is a non-owning,
// possibly strided window (an ROI) into one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <variant>
#include <vector>

namespace lt {

template <typename T>
struct ImageView {
  const T* data = nullptr;
  int width = 0;
  int height = 0;
  int channels = 1;
  ptrdiff_t row_stride = 0;  // elements (not bytes) between the starts of two rows

  const T* Row(int y) const { return data + ptrdiff_t(y) * row_stride; }
  const T& At(int x, int y, int c = 0) const { return Row(y)[ptrdiff_t(x) * channels + c]; }
  bool empty() const { return width <= 0 || height <= 0; }
  // A rectangular window; throws std::out_of_range when it leaves the image.
  ImageView Crop(int x, int y, int w, int h) const {
    if (x < 0 || y < 0 || w <= 0 || h <= 0 || x + w > width || y + h > height) {
      throw std::out_of_range("crop window outside the image");
    }
    return {Row(y) + ptrdiff_t(x) * channels, w, h, channels, row_stride};
  }
};

template <typename T>
struct Image {
  int width = 0;
  int height = 0;
  int channels = 1;
  std::vector<T> pixels;  // width * height * channels

  Image() = default;
  Image(int w, int h, int c = 1, T fill = T{}) : width(w), height(h), channels(c), pixels(size_t(w) * h * c, fill) {}

  T* Row(int y) { return pixels.data() + size_t(y) * width * channels; }
  const T* Row(int y) const { return pixels.data() + size_t(y) * width * channels; }
  T& At(int x, int y, int c = 0) { return Row(y)[size_t(x) * channels + c]; }
  const T& At(int x, int y, int c = 0) const { return Row(y)[size_t(x) * channels + c]; }
  bool empty() const { return width <= 0 || height <= 0; }
  ImageView<T> View() const { return {pixels.data(), width, height, channels, ptrdiff_t(width) * channels}; }
};

// An image as read from a file, in its own sample type: 8-bit and 16-bit files
// keep their integer values (0..255, 0..65535); float files (EXR, float TIFF) stay float.
using AnyImage = std::variant<Image<uint8_t>, Image<uint16_t>, Image<float>>;

}  // namespace lt
