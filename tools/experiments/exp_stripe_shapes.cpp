// Stripe extraction on stripe shapes unlike the Gaussian ones the methods were
// tuned on (docs/extraction.md, "Audit on unseen stripe shapes"): thin, wide,
// flat-topped, saturated, asymmetric, close pairs of unequal brightness, noise
// islands, low SNR, noise only, steep tilts, speckle, wide stripes near the
// border. Each frame is a profile P(d) of the distance d across a straight
// centre line, integrated over each pixel by 8x8 sub-samples (a sharp edge's
// pixel fractions are thus exact to 1/64), then noise; the truth is the line.
// Prints one markdown table: per frame and method, the search lines with a
// point matched to a stripe (within `match` px) of the lines where a stripe is
// inside the frame, the points matched to none, and the RMS / max |error|.
//
//   build/bin/exp_stripe_shapes
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "tools/experiments/stripe_frames.h"

namespace {

using namespace exp_stripes;

void Row(const std::string& name, const Frame& f, double threshold, double background = 0, double match = 3,
         bool local = false) {
  const lt::Image<float> img = Render(f);
  std::printf("| %s |", name.c_str());
  for (auto m : {lt::ExtractionMethod::kMax, lt::ExtractionMethod::kCom, lt::ExtractionMethod::kMultiCom,
                 lt::ExtractionMethod::kSteger}) {
    lt::ExtractionOptions o;
    o.method = m;
    o.threshold = threshold;
    o.background = background;
    if (local) o.background_mode = lt::BackgroundMode::kLocal;
    const Cell c = Measure(f, img.View(), o, match);
    std::printf(" %d/%d", c.found, c.lines);
    if (c.unmatched) std::printf(" +%d", c.unmatched);
    if (c.found) std::printf(", %.3f / %.3f", c.rms, c.max_abs);
    std::printf(" |");
  }
  std::printf("\n");
}

Frame One(Profile p, double angle = 5, double u0 = 80.3, int width = 160) {
  Frame f;
  f.width = width;
  f.stripes.push_back({u0, 48, angle, std::move(p)});
  return f;
}

}  // namespace

int main() {
  std::printf("| frame | max | com | multicom | steger |\n| --- | --- | --- | --- | --- |\n");
  char name[128];
  for (double s : {0.3, 0.5, 0.7}) {
    std::snprintf(name, sizeof name, "thin, sigma %.1f, 1.2 deg", s);
    Row(name, One(Gauss(1000, s), 1.2), 100);
  }
  for (double s : {8.0, 12.0, 20.0}) {
    Frame f = One(Gauss(1000, s), 5, 160.3, 320);
    f.noise = 10;
    std::snprintf(name, sizeof name, "wide, sigma %.0f, 1%% noise, 320 px", s);
    Row(name, f, 100);
  }
  for (double s : {8.0, 12.0})
    for (double u : {15.0, 25.0, 35.0}) {
      Frame f = One(Gauss(1000, s), 0, u);
      f.noise = 10;
      std::snprintf(name, sizeof name, "wide, sigma %.0f, %.0f px from the border", s, u);
      Row(name, f, 100);
    }
  for (double w : {5.0, 10.0, 20.0}) {
    Frame f = One(FlatTop(1000, w, 0.7));
    f.noise = 10;
    std::snprintf(name, sizeof name, "flat top %.0f px, soft edges, 1%% noise", w);
    Row(name, f, 100);
  }
  for (double s : {1.0, 2.0, 4.0}) {
    Frame f = One(Gauss(2550, s));
    f.level = 8, f.noise = 2, f.clip = 255;
    std::snprintf(name, sizeof name, "8-bit, sigma %.0f, 10x saturated, 2 DN", s);
    Row(name, f, 25.5, 8);
  }
  for (double s : {1.0, 3.0}) {
    Frame f = One(Gauss(20 * 4095, s));
    f.level = 64, f.noise = 8, f.clip = 4095;
    std::snprintf(name, sizeof name, "12-bit in 16, sigma %.0f, 20x saturated", s);
    Row(name, f, 409.5, 64);
  }
  for (double tail : {2.0, 6.0}) {
    std::snprintf(name, sizeof name, "tail %.0f px at 0.5 (truth: the peak)", tail);
    Row(name, One(Tail(1000, 1.5, tail, 0.5)), 100, 0, 10);
  }
  for (double gap : {6.0, 7.0, 8.0})
    for (double ratio : {0.3, 0.5}) {
      Frame f = One(Gauss(1000, 1.5), 5, 78);
      f.stripes.push_back({78 + gap, 48, 5, Gauss(1000 * ratio, 1.5)});
      std::snprintf(name, sizeof name, "two, %.0f px apart, right one %.1f", gap, ratio);
      Row(name, f, 100, 0, gap / 2);
    }
  for (double s : {4.0, 8.0}) {
    Frame f = One(Gauss(1000, s));
    f.level = 20, f.noise = 30;
    std::snprintf(name, sizeof name, "sigma %.0f, 3%% noise, threshold 120 (islands)", s);
    Row(name, f, 120, 20);
  }
  for (double k : {1.0, 1.5}) {
    Frame f = One(Gauss(100 * k, 2));
    f.level = 20, f.noise = 25;
    std::snprintf(name, sizeof name, "peak %.1fx the threshold, noise 25%% of it", k);
    Row(name, f, 100, 20);
  }
  for (double bg : {0.0, 20.0}) {
    Frame f;
    f.level = 20, f.noise = 30;
    std::snprintf(name, sizeof name, "noise only, sigma 30 on 20, --background %.0f", bg);
    Row(name, f, 100, bg);
  }
  for (double a : {45.0, 60.0, 70.0}) {
    Frame f = One(Gauss(1000, 1.5), a);
    f.noise = 10;
    std::snprintf(name, sizeof name, "tilt %.0f deg, sigma 1.5, 1%% noise", a);
    Row(name, f, 100, 0, 4);
  }
  for (double c : {0.2, 0.4}) {
    Frame f = One(Gauss(1000, 2));
    f.speckle = c;
    std::snprintf(name, sizeof name, "speckle %.0f%%, grain 1 px, sigma 2", c * 100);
    Row(name, f, 100, 0, 6);
  }
  return 0;
}
