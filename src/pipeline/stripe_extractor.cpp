#include "pipeline/stripe_extractor.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include <tbb/task_arena.h>

#include "core/error.h"
#include "core/text_fields.h"
#include "pipeline/demosaic.h"
#include "pipeline/extract_methods.h"
#include "pipeline/extract_steger.h"
#include "pipeline/extract_transfer.h"
#include "pipeline/steger_width.h"

namespace lt {

namespace {

template <typename T>
double FullScale() {
  if constexpr (std::is_integral_v<T>) return double(std::numeric_limits<T>::max());
  return 1.0;
}

// Whether every pixel holds the same value in all its channels (a grey image
// stored as colour).
template <typename T>
bool ChannelsAreEqual(const ImageView<T>& view) {
  const int C = view.channels;
  for (int y = 0; y < view.height; ++y) {
    const T* row = view.Row(y);
    for (int x = 0; x < view.width; ++x) {
      for (int c = 1; c < C; ++c) {
        if (row[x * C + c] != row[x * C]) return false;
      }
    }
  }
  return true;
}

// Copies `src` transposed into `dst` (dst row i = src column i).
template <typename T>
void Transpose(const ImageView<T>& src, T* dst) {
  constexpr int kBlock = 32;
  const int W = src.width, H = src.height;
  for (int y0 = 0; y0 < H; y0 += kBlock) {
    for (int x0 = 0; x0 < W; x0 += kBlock) {
      for (int x = x0; x < std::min(W, x0 + kBlock); ++x) {
        T* out = dst + size_t(x) * H;
        for (int y = y0; y < std::min(H, y0 + kBlock); ++y) out[y] = src.Row(y)[x];
      }
    }
  }
}

}  // namespace

struct StripeExtractor::Impl {
  ExtractionOptions options;
  ExtractionOptions resolved;  // options with steger's width of the last frame
  tbb::task_arena arena;
  BandedPoints banded;
  std::unique_ptr<StegerDetector> steger;
  std::vector<StripePoint> width_peaks;
  std::vector<uint8_t> buf8[2];
  std::vector<uint16_t> buf16[2];
  std::vector<float> buf32[2];
  std::vector<float> demosaiced;  // R, G, B of a Bayer mosaic
  std::vector<float> transfer_table, linear;  // options.transfer's table, the linearized image
  WidthRejections rejections;     // of the last Extract
  NoiseThreshold noise_threshold;  // of the last Extract (threshold_mode kNoise)
  bool has_noise_threshold = false;
  double mosaic_noise = 0;  // kNoise on a Bayer mosaic: the noise bound from the raw mosaic (NaN: none)
  SampleScale scale;        // kNoise: the search lines' quantization step and full scale

  explicit Impl(ExtractionOptions o)
      : options((o.Check(), std::move(o))),
        resolved(options),
        arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic) {
    if (options.threshold_mode == ThresholdMode::kNoise) resolved.threshold = ExtractionOptions::kAuto;
    if (options.method != ExtractionMethod::kSteger) return;
    if (std::isnan(resolved.expected_width)) resolved.expected_width = ExtractionOptions::kDefaultExpectedWidth;
    steger = std::make_unique<StegerDetector>(resolved);
  }

  // With an automatic width: measures it on `work` and sets the detector up for it.
  template <typename T>
  void ResolveStegerWidth(const ImageView<T>& work, const MethodParams& params) {
    if (!std::isnan(options.expected_width)) return;
    ExtractMax(work, params, &banded);
    width_peaks.clear();
    WidthRejections ignored;
    banded.AppendTo(&width_peaks, &ignored);
    const double w = MeasureStegerWidth(work, params.options->background, &width_peaks);
    if (w == resolved.expected_width) return;
    resolved.expected_width = w;
    steger->Configure(resolved);
  }

  template <typename T>
  std::vector<T>& Buffer(int slot) {
    if constexpr (std::is_same_v<T, uint8_t>) return buf8[slot];
    else if constexpr (std::is_same_v<T, uint16_t>) return buf16[slot];
    else return buf32[slot];
  }

  // Runs the method on a mono image whose rows are search lines; appends
  // points in that image's coordinates.
  template <typename T>
  void RunMethod(const ImageView<T>& work, const MethodParams& given, std::vector<StripePoint>* points) {
    MethodParams params = given;
    if (options.threshold_mode == ThresholdMode::kNoise) {
      // The frame's own threshold (pipeline/auto_threshold.h) on the search
      // lines; a height above the background with the local background and
      // for steger (its threshold is a contrast, blind to the background).
      noise_threshold = EstimateNoiseThreshold(
          work, scale,
          options.background_mode == BackgroundMode::kLocal || options.method == ExtractionMethod::kSteger,
          mosaic_noise);
      has_noise_threshold = true;
      params.threshold = noise_threshold.threshold;
      params.high_threshold = std::isnan(options.high_threshold) ? params.threshold
                                                                 : std::max(options.high_threshold, params.threshold);
      resolved.threshold = params.threshold;
    }
    arena.execute([&] {
      switch (options.method) {
        case ExtractionMethod::kMax:
          ExtractMax(work, params, &banded);
          banded.AppendTo(points, &rejections);
          break;
        case ExtractionMethod::kCom:
          ExtractCom(work, params, &banded);
          banded.AppendTo(points, &rejections);
          break;
        case ExtractionMethod::kMultiCom:
          ExtractMultiCom(work, params, &banded);
          banded.AppendTo(points, &rejections);
          break;
        case ExtractionMethod::kSteger:
          ResolveStegerWidth(work, params);
          steger->Run(work, params, points);
          break;
      }
    });
  }

  // Orients (transposes for column search) and runs.
  template <typename T>
  void RunOriented(const ImageView<T>& mono, const MethodParams& params, std::vector<StripePoint>* points) {
    if (options.axis == SearchAxis::kRows) {
      RunMethod(mono, params, points);
      return;
    }
    auto& buf = Buffer<T>(1);
    buf.resize(size_t(mono.width) * mono.height);
    Transpose(mono, buf.data());
    ImageView<T> work{buf.data(), mono.height, mono.width, 1, ptrdiff_t(mono.height)};
    RunMethod(work, params, points);
    for (auto& p : *points) std::swap(p.u, p.v);
  }
};

StripeExtractor::StripeExtractor(ExtractionOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {}
StripeExtractor::~StripeExtractor() = default;

const ExtractionOptions& StripeExtractor::options() const { return impl_->options; }
const ExtractionOptions& StripeExtractor::resolved_options() const { return impl_->resolved; }
const WidthRejections& StripeExtractor::last_rejections() const { return impl_->rejections; }
const NoiseThreshold* StripeExtractor::last_noise_threshold() const {
  return impl_->has_noise_threshold ? &impl_->noise_threshold : nullptr;
}

template <typename T>
double StripeExtractor::ThresholdFor() const {
  if (impl_->options.threshold_mode == ThresholdMode::kNoise) return impl_->resolved.threshold;
  const double t = impl_->options.threshold;
  return std::isnan(t) ? 0.1 * FullScale<T>() * impl_->options.WeightedFullScale() : t;
}

template <typename T>
void StripeExtractor::Extract(const ImageView<T>& image, std::vector<StripePoint>* points) {
  const ExtractionOptions& o = impl_->options;
  points->clear();
  impl_->rejections = {};
  if (image.data == nullptr || image.empty()) {
    throw InputError("", "image is empty (" + SizeText(image.width, image.height) + ")");
  }
  const bool noise_mode = o.threshold_mode == ThresholdMode::kNoise;
  if (o.transfer == Transfer::kLinear) {
    if (noise_mode) impl_->scale = MeasureSampleScale(image);
    return ExtractLinear(image, ThresholdFor<T>(), points);
  }
  if constexpr (std::is_floating_point_v<T>) {
    throw InputError("", "a float image holds linear values: --transfer applies to 8- and 16-bit images");
  } else {
    if (noise_mode) {
      // The linearized samples are still quantized: their step is the curve's
      // step at the background's code value (median), one code step wide.
      SampleScale& scale = impl_->scale;
      scale = MeasureSampleScale(image);
      const double full = scale.full;
      const double lo = std::clamp(scale.median - 0.5 * scale.step, 0.0, full - scale.step);
      scale.step = full * (DecodeTransfer(o.transfer, o.gamma, (lo + scale.step) / full) -
                           DecodeTransfer(o.transfer, o.gamma, lo / full));
    }
    // Linear values on the image's own scale: the threshold is T's.
    ExtractLinear(LinearizeImage(image, o.transfer, o.gamma, &impl_->transfer_table, &impl_->linear),
                  ThresholdFor<T>(), points);
  }
}

template <typename T>
void StripeExtractor::ExtractLinear(const ImageView<T>& image, double threshold, std::vector<StripePoint>* points) {
  const ExtractionOptions& o = impl_->options;
  if (image.channels < 1) throw InputError("", "image has no channels");
  ImageView<T> view = image;
  PixelRect region{0, 0, image.width, image.height};
  if (o.roi) {
    const PixelRect& r = *o.roi;
    if (r.x < 0 || r.y < 0 || r.width <= 0 || r.height <= 0 || int64_t(r.x) + r.width > image.width ||
        int64_t(r.y) + r.height > image.height) {
      throw InputError("", "ROI " + std::to_string(r.x) + "," + std::to_string(r.y) + "," + std::to_string(r.width) +
                               "," + std::to_string(r.height) + " is not inside the " +
                               SizeText(image.width, image.height) + " image");
    }
    view = image.Crop(r.x, r.y, r.width, r.height);
    region = r;
  }
  const bool bayer = o.bayer != ColorFilter::kMono;
  if (bayer && image.channels != 1) {
    throw InputError("", std::string("a Bayer mosaic (") + BayerPatternName(o.bayer) +
                             ") has one channel but the image has " + std::to_string(image.channels) +
                             ": it is not a raw mosaic");
  }
  const int C = bayer ? 3 : image.channels;  // channels to choose from (a mosaic's: demosaiced R, G, B)
  const char* channels_of = bayer ? " but the demosaiced Bayer image has " : " but the image has ";
  if (o.channel >= C) {
    throw InputError("", "channel " + std::to_string(o.channel) + " requested" + channels_of +
                             std::to_string(C) + (C == 1 ? " channel" : " channels"));
  }
  if (!o.channel_weights.empty() && int(o.channel_weights.size()) != C) {
    throw InputError("", std::to_string(o.channel_weights.size()) + " channel weights given" + channels_of +
                             std::to_string(C) + (C == 1 ? " channel" : " channels"));
  }
  // A grey image stored in colour channels (as many tools save monochrome frames:
  // BMP, PPM, GIF, WebP, RGB PNG) has one brightness: its first channel. A colour
  // image needs the laser's channel named.
  int channel = o.channel;
  if (!bayer && C > 1 && o.channel < 0 && o.channel_weights.empty()) {
    if (!ChannelsAreEqual(view)) {
      throw InputError("", "the image has " + std::to_string(C) +
                               " channels: choose the laser's channel (--channel, 0-based) or give channel weights (--weights, e.g. 1,0,0 for red)");
    }
    channel = 0;
  }
  if constexpr (std::is_floating_point_v<T>) {
    for (int y = 0; y < view.height; ++y) {
      const T* row = view.Row(y);
      bool ok = true;
      for (int i = 0; i < view.width * view.channels; ++i) ok &= std::isfinite(row[i]);
      if (!ok) throw InputError("", "image row " + std::to_string(region.y + y) + " holds NaN or infinite values");
    }
  }
  impl_->mosaic_noise = ExtractionOptions::kAuto;
  MethodParams params;
  params.options = &o;
  params.threshold = threshold;
  params.high_threshold = std::isnan(o.high_threshold) ? params.threshold : o.high_threshold;
  const int W = view.width, H = view.height;
  if (bayer) {
    // Demosaiced R, G, B (the crop keeps the sensor's mosaic phase), then their
    // mean, one of them or their weighted sum.
    std::vector<float>& rgb = impl_->demosaiced;
    DemosaicBilinear(view, o.bayer, region.x, region.y, &rgb);
    double w[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
    if (o.channel >= 0) {
      for (int c = 0; c < 3; ++c) w[c] = c == o.channel ? 1.0 : 0.0;
    } else if (!o.channel_weights.empty()) {
      for (int c = 0; c < 3; ++c) w[c] = o.channel_weights[size_t(c)];
    }
    if (o.threshold_mode == ThresholdMode::kNoise) {
      // Each colour's own noise (a red-lit frame's R is noisier than G).
      impl_->mosaic_noise = MosaicNoise(view, o.bayer, region.x, region.y, w, impl_->scale.step);
      // The mix is not on the samples' grid; its full scale is the positive weights'.
      impl_->scale.full *= o.WeightedFullScale();
      impl_->scale.step = 0;
    }
    auto& buf = impl_->Buffer<float>(0);
    buf.resize(size_t(W) * H);
    const float w0 = float(w[0]), w1 = float(w[1]), w2 = float(w[2]);
    for (size_t i = 0; i < buf.size(); ++i) buf[i] = w0 * rgb[3 * i] + w1 * rgb[3 * i + 1] + w2 * rgb[3 * i + 2];
    impl_->RunOriented(ImageView<float>{buf.data(), W, H, 1, ptrdiff_t(W)}, params, points);
  } else if (!o.channel_weights.empty() && !(C == 1 && o.channel_weights[0] == 1.0)) {
    if (o.threshold_mode == ThresholdMode::kNoise) {  // the mix is not on the samples' grid
      impl_->scale.full *= o.WeightedFullScale();
      impl_->scale.step = 0;
    }
    auto& buf = impl_->Buffer<float>(0);
    buf.resize(size_t(W) * H);
    for (int y = 0; y < H; ++y) {
      const T* row = view.Row(y);
      float* out = buf.data() + size_t(y) * W;
      for (int x = 0; x < W; ++x) {
        double s = 0;
        for (int c = 0; c < C; ++c) s += o.channel_weights[c] * double(row[x * C + c]);
        out[x] = float(s);
      }
    }
    impl_->RunOriented(ImageView<float>{buf.data(), W, H, 1, ptrdiff_t(W)}, params, points);
  } else if (C > 1) {
    auto& buf = impl_->Buffer<T>(0);
    buf.resize(size_t(W) * H);
    const int c = channel;
    for (int y = 0; y < H; ++y) {
      const T* row = view.Row(y);
      T* out = buf.data() + size_t(y) * W;
      for (int x = 0; x < W; ++x) out[x] = row[x * C + c];
    }
    impl_->RunOriented(ImageView<T>{buf.data(), W, H, 1, ptrdiff_t(W)}, params, points);
  } else {
    impl_->RunOriented(view, params, points);
  }
  for (auto& p : *points) {
    p.u += region.x;
    p.v += region.y;
  }
}

std::vector<StripePoint> StripeExtractor::Extract(const AnyImage& image) {
  return std::visit([&](const auto& img) { return Extract(img.View()); }, image);
}

#define LT_INSTANTIATE(T)                                                                  \
  template void StripeExtractor::Extract<T>(const ImageView<T>&, std::vector<StripePoint>*); \
  template double StripeExtractor::ThresholdFor<T>() const;
LT_INSTANTIATE(uint8_t)
LT_INSTANTIATE(uint16_t)
LT_INSTANTIATE(float)
#undef LT_INSTANTIATE

}  // namespace lt
