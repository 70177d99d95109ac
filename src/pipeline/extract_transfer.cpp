#include "pipeline/extract_transfer.h"

#include <cmath>
#include <limits>

namespace lt {

double DecodeTransfer(Transfer transfer, double gamma, double encoded) {
  switch (transfer) {
    case Transfer::kLinear: return encoded;
    case Transfer::kSrgb:  // IEC 61966-2-1
      return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
    case Transfer::kGamma: return std::pow(encoded, gamma);
  }
  return encoded;
}

template <typename T>
ImageView<float> LinearizeImage(const ImageView<T>& image, Transfer transfer, double gamma,
                                std::vector<float>* table, std::vector<float>* out) {
  static_assert(std::is_integral_v<T>, "a float image is linear");
  constexpr int kMax = std::numeric_limits<T>::max();
  // The table's last two entries remember what it was built for.
  const float tag_transfer = float(int(transfer)), tag_gamma = float(gamma);
  if (table->size() != size_t(kMax) + 3 || (*table)[kMax + 1] != tag_transfer || (*table)[kMax + 2] != tag_gamma) {
    table->resize(size_t(kMax) + 3);
    for (int v = 0; v <= kMax; ++v) (*table)[v] = float(kMax * DecodeTransfer(transfer, gamma, double(v) / kMax));
    (*table)[kMax + 1] = tag_transfer;
    (*table)[kMax + 2] = tag_gamma;
  }
  const int n = image.width * image.channels;
  out->resize(size_t(n) * image.height);
  const float* t = table->data();
  for (int y = 0; y < image.height; ++y) {
    const T* row = image.Row(y);
    float* o = out->data() + size_t(y) * n;
    for (int i = 0; i < n; ++i) o[i] = t[row[i]];
  }
  return ImageView<float>{out->data(), image.width, image.height, image.channels, ptrdiff_t(n)};
}

template ImageView<float> LinearizeImage(const ImageView<uint8_t>&, Transfer, double, std::vector<float>*,
                                         std::vector<float>*);
template ImageView<float> LinearizeImage(const ImageView<uint16_t>&, Transfer, double, std::vector<float>*,
                                         std::vector<float>*);

}  // namespace lt
