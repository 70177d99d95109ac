#include "pipeline/extraction_options.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "core/error.h"
#include "core/text_fields.h"

#include "pipeline/option_checks.h"

namespace lt {

const char* MethodName(ExtractionMethod method) {
  switch (method) {
    case ExtractionMethod::kMax: return "max";
    case ExtractionMethod::kCom: return "com";
    case ExtractionMethod::kMultiCom: return "multicom";
    case ExtractionMethod::kSteger: return "steger";
  }
  return "?";
}

const char* AxisName(SearchAxis axis) { return axis == SearchAxis::kRows ? "rows" : "cols"; }

ExtractionMethod ParseMethod(const std::string& text, const std::string& where) {
  for (auto m : {ExtractionMethod::kMax, ExtractionMethod::kCom, ExtractionMethod::kMultiCom, ExtractionMethod::kSteger}) {
    if (text == MethodName(m)) return m;
  }
  throw InputError(where, "unknown extraction method '" + text + "' (expected max, com, multicom or steger)");
}

SearchAxis ParseAxis(const std::string& text, const std::string& where) {
  if (text == "rows") return SearchAxis::kRows;
  if (text == "cols") return SearchAxis::kCols;
  throw InputError(where, "unknown search axis '" + text + "' (expected rows or cols)");
}

std::vector<double> ParseNumberList(const std::string& text, const std::string& where) {
  std::vector<double> values;
  std::stringstream ss(text);
  for (std::string f; std::getline(ss, f, ',');) {
    const std::optional<double> v = ParseFiniteNumber(TrimBlanks(f));
    if (!v) throw InputError(where, "'" + f + "' is not a number");
    values.push_back(*v);
  }
  return values;
}

PixelRect ParseRoi(const std::string& text, const std::string& where) {
  const std::vector<double> v = ParseNumberList(text, where);
  if (v.size() != 4) throw InputError(where, "expected X,Y,W,H, got '" + text + "'");
  for (double x : v) {
    if (x != std::floor(x) || std::abs(x) > 1e9) throw InputError(where, "expected whole pixel numbers, got '" + text + "'");
  }
  return {int(v[0]), int(v[1]), int(v[2]), int(v[3])};
}

void ParseBackground(const std::string& text, const std::string& where, double* level, BackgroundMode* mode) {
  if (text == "local") {
    *mode = BackgroundMode::kLocal;
    return;
  }
  const std::optional<double> v = ParseFiniteNumber(TrimBlanks(text));
  if (!v) throw InputError(where, "expected a level (a number) or 'local', got '" + text + "'");
  *level = *v;
  *mode = BackgroundMode::kLevel;
}

void ParseThreshold(const std::string& text, const std::string& where, double* threshold, ThresholdMode* mode) {
  const std::string t(TrimBlanks(text));
  if (t == "auto") {
    *mode = ThresholdMode::kNoise;
    return;
  }
  const std::optional<double> v = ParseFiniteNumber(t);
  if (!v) throw InputError(where, "expected a finite number or 'auto', got '" + text + "'");
  *threshold = *v;
  *mode = ThresholdMode::kFixed;
}

void ParseTransfer(const std::string& text, const std::string& where, Transfer* transfer, double* gamma) {
  const std::string t(TrimBlanks(text));
  if (t == "linear" || t == "srgb") {
    *transfer = t == "linear" ? Transfer::kLinear : Transfer::kSrgb;
    return;
  }
  if (t.rfind("gamma=", 0) == 0) {
    const std::optional<double> g = ParseFiniteNumber(t.substr(6));
    if (g && *g >= 1 && *g <= 4) {
      *transfer = Transfer::kGamma;
      *gamma = *g;
      return;
    }
  }
  throw InputError(where, "expected linear, srgb or gamma=G with G in [1, 4] (e.g. gamma=2.2), got '" + text + "'");
}

namespace {
bool FiniteOrAuto(double v) { return std::isnan(v) || std::isfinite(v); }
}  // namespace

void ExtractionOptions::Check() const {
  if (roi) {
    Require(roi->x >= 0 && roi->y >= 0, "roi", "must start inside the image (x, y >= 0)");
    Require(roi->width > 0 && roi->height > 0, "roi", "must have a positive width and height");
  }
  Require(FiniteOrAuto(threshold) && !(threshold < 0), "threshold", "must be >= 0, got " + FormatNumber(threshold));
  Require(FiniteOrAuto(high_threshold) && !(high_threshold < 0), "high_threshold",
          "must be >= 0, got " + FormatNumber(high_threshold));
  if (threshold_mode == ThresholdMode::kFixed && !std::isnan(threshold) && !std::isnan(high_threshold)) {
    Require(high_threshold >= threshold, "high_threshold",
            "must be >= threshold (" + FormatNumber(threshold) + "), got " + FormatNumber(high_threshold));
  }
  Require(std::isfinite(background), "background", "must be finite");
  Require(window >= 0 && window <= 1000, "window", "must be in [0, 1000] pixels, got " + std::to_string(window));
  Require(std::isfinite(min_width) && min_width >= 0, "min_width", "must be >= 0, got " + FormatNumber(min_width));
  Require(std::isfinite(max_width) && max_width >= 0, "max_width", "must be >= 0, got " + FormatNumber(max_width));
  Require(max_width == 0 || max_width >= min_width, "max_width",
          "must be 0 (no limit) or >= min_width, got " + FormatNumber(max_width));
  Require(FiniteOrAuto(expected_width) && !(expected_width <= 0) && !(expected_width > 200), "expected_width",
          "must be in (0, 200] pixels, got " + FormatNumber(expected_width));
  Require(std::isfinite(sigma) && sigma >= 0 && sigma <= 50, "sigma",
          "must be 0 (automatic) or in (0, 50] pixels, got " + FormatNumber(sigma));
  Require(sigma == 0 || sigma >= 0.5, "sigma", "must be >= 0.5 pixels, got " + FormatNumber(sigma));
  Require(std::isfinite(max_angle_deg) && max_angle_deg > 0 && max_angle_deg < 90, "max_angle_deg",
          "must be in (0, 90) degrees, got " + FormatNumber(max_angle_deg));
  Require(channel >= -1, "channel", "must be >= 0, got " + std::to_string(channel));
  Require(channel < 0 || channel_weights.empty(), "channel", "give either a channel or channel weights, not both");
  if (!channel_weights.empty()) {
    double sum = 0;
    for (double w : channel_weights) {
      Require(std::isfinite(w), "channel_weights", "must be finite");
      sum += std::abs(w);
    }
    Require(sum > 0, "channel_weights", "must not all be zero");
  }
  if (bayer != ColorFilter::kMono) {
    Require(channel < 3, "channel",
            "a demosaiced Bayer image has 3 channels (R, G, B): must be 0, 1 or 2, got " + std::to_string(channel));
    Require(channel_weights.empty() || channel_weights.size() == 3, "channel_weights",
            "a demosaiced Bayer image has 3 channels (R, G, B): give 3 weights, got " +
                std::to_string(channel_weights.size()));
  }
  Require(transfer != Transfer::kGamma || (std::isfinite(gamma) && gamma >= 1 && gamma <= 4), "gamma",
          "must be in [1, 4], got " + FormatNumber(gamma));
  Require(threads >= 0 && threads <= 1024, "threads", "must be in [0, 1024], got " + std::to_string(threads));
}

double ExtractionOptions::WeightedFullScale() const {
  if (channel >= 0 || channel_weights.empty()) return 1.0;
  double sum = 0;
  for (double w : channel_weights) sum += std::max(w, 0.0);
  return sum;
}

double ExtractionOptions::WeightedLevel() const {
  if (channel >= 0 || channel_weights.empty()) return 1.0;
  double sum = 0;
  for (double w : channel_weights) sum += w;
  return sum;
}

double ExtractionOptions::SigmaUsed() const {
  if (sigma > 0) return sigma;
  const double w = std::isnan(expected_width) ? kDefaultExpectedWidth : expected_width;
  return std::max(1.0, w / (2.0 * std::sqrt(3.0)));
}

int ExtractionOptions::EdgeLinesWithoutPoints() const {
  return method == ExtractionMethod::kSteger ? int(std::ceil(3.0 * SigmaUsed())) : 0;
}

int UnscaledBitDepth(double brightest) {
  int bits = 1;
  while (bits < 16 && brightest > std::ldexp(1.0, bits) - 1) ++bits;
  return bits >= 8 && bits < 16 ? bits : 0;
}

}  // namespace lt
