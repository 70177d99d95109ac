#include "render/film.h"

#include <gtest/gtest.h>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <cstring>

#include "core/error.h"
#include "core/random.h"

namespace lt {
namespace {

using Eigen::Vector3f;

FilmOptions Options(int w, int h, int sheets) {
  FilmOptions o;
  o.width = w;
  o.height = h;
  o.laser_sheets = sheets;
  return o;
}

// The deterministic sample i of pixel p: what a renderer would trace.
struct Sample {
  Vector3f rgb;
  std::array<float, 3> laser;
};
Sample MakeSample(int pixel, int i) {
  Rng rng = Rng::For(1, 0, uint64_t(pixel), uint64_t(i));
  Sample s;
  s.rgb = Vector3f(rng.NextFloat(), rng.NextFloat(), rng.NextFloat());
  // Sheet 2 dominates in even pixels, sheet 0 in odd ones; sheet 1 is dim.
  s.laser = {rng.NextFloat() * (pixel % 2 ? 4.0f : 1.0f), 0.1f * rng.NextFloat(),
             rng.NextFloat() * (pixel % 2 ? 1.0f : 4.0f)};
  return s;
}

TEST(Film, MeansCountsAndDominantSheet) {
  Film film(Options(4, 3, 3));
  const int n = 50;
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 4; ++x) {
      const int p = y * 4 + x;
      for (int i = 0; i < n + p; ++i) {
        const Sample s = MakeSample(p, i);
        film.AddSample(x, y, s.rgb, s.laser);
      }
    }
  }
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 4; ++x) {
      const int p = y * 4 + x, count = n + p;
      EXPECT_EQ(film.SampleCount(x, y), uint32_t(count));
      double rgb[3] = {0, 0, 0}, laser[3] = {0, 0, 0};
      for (int i = 0; i < count; ++i) {
        const Sample s = MakeSample(p, i);
        for (int c = 0; c < 3; ++c) {
          rgb[c] += s.rgb[c];
          laser[c] += s.laser[c];
        }
      }
      // Float sums of 50-61 values in [0, 4]: relative rounding below 1e-5.
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(film.MeanRgb(x, y)[c], rgb[c] / count, 1e-5);
        EXPECT_NEAR(film.MeanLaser(x, y, c), laser[c] / count, 1e-5);
      }
      EXPECT_NEAR(film.MeanLaserTotal(x, y), (laser[0] + laser[1] + laser[2]) / count, 1e-5);
      EXPECT_EQ(film.DominantSheet(x, y), p % 2 ? 0 : 2);
    }
  }
  const Image<float> rgb = film.RgbImage();
  EXPECT_EQ(rgb.channels, 3);
  EXPECT_EQ(rgb.At(3, 2, 1), film.MeanRgb(3, 2)[1]);
  EXPECT_EQ(film.LaserImage().At(1, 1), film.MeanLaserTotal(1, 1));
  EXPECT_EQ(film.LaserSheetImage(2).At(2, 0), film.MeanLaser(2, 0, 2));
  EXPECT_EQ(film.DominantSheetImage().At(1, 0), 0);
  EXPECT_EQ(film.SampleCountImage().At(3, 2), uint32_t(n + 11));
  EXPECT_THROW(film.LaserSheetImage(3), std::out_of_range);
}

TEST(Film, UnlitPixels) {
  Film film(Options(2, 1, 2));
  EXPECT_EQ(film.DominantSheet(0, 0), -1);
  EXPECT_EQ(film.MeanRgb(0, 0), Vector3f::Zero());
  EXPECT_EQ(film.Variance(0, 0), 0.0f);
  EXPECT_TRUE(std::isinf(film.RelativeStandardError(0, 0, 1e-3f)));
  const float dark[2] = {0.0f, 0.0f};
  film.AddSample(0, 0, Vector3f(1, 1, 1), dark);
  EXPECT_EQ(film.DominantSheet(0, 0), -1);  // broadband light only
  EXPECT_EQ(film.Variance(0, 0), 0.0f);     // one sample
  Film no_laser(Options(1, 1, 0));
  no_laser.AddSample(0, 0, Vector3f(0.5f, 0, 0), {});
  EXPECT_EQ(no_laser.DominantSheet(0, 0), -1);
  EXPECT_EQ(no_laser.LaserImage().At(0, 0), 0.0f);
  EXPECT_THROW(no_laser.AddSample(0, 0, Vector3f::Zero(), dark), std::invalid_argument);
}

// Welford's running variance equals the two-pass variance of the tracked
// scalar v = rgb_weights . rgb + laser_weight * sum(laser), to float rounding
// (values around 1, 2000 samples: 1e-4 relative), and the relative standard
// error follows from it.
TEST(Film, WelfordVariance) {
  FilmOptions o = Options(1, 1, 3);
  o.rgb_weights = Vector3f(0.5f, 1.0f, 2.0f);
  o.laser_weight = 3.0f;
  Film film(o);
  const int n = 2000;
  double sum = 0, sum2 = 0;
  std::vector<double> values;
  for (int i = 0; i < n; ++i) {
    const Sample s = MakeSample(0, i);
    film.AddSample(0, 0, s.rgb, s.laser);
    values.push_back(0.5 * s.rgb[0] + s.rgb[1] + 2 * s.rgb[2] + 3.0 * (s.laser[0] + s.laser[1] + s.laser[2]));
  }
  for (double v : values) sum += v;
  const double mean = sum / n;
  for (double v : values) sum2 += (v - mean) * (v - mean);
  const double var = sum2 / (n - 1);
  EXPECT_NEAR(film.MeanValue(0, 0), mean, 1e-4 * mean);
  EXPECT_NEAR(film.Variance(0, 0), var, 1e-4 * var);
  EXPECT_NEAR(film.RelativeStandardError(0, 0, 1e-6f), std::sqrt(var / n) / mean, 1e-4 * std::sqrt(var / n) / mean);
  // A dark pixel: the floor bounds the relative error.
  EXPECT_NEAR(film.RelativeStandardError(0, 0, 100.0f * float(mean)), std::sqrt(var / n) / (100 * mean), 1e-6);
}

// Tiles accumulated in parallel (each pixel written by one task) give the
// same bytes as a serial pass.
TEST(Film, ParallelTilesMatchSerial) {
  const int w = 97, h = 61, spp = 16;
  auto render_pixel = [&](Film& film, int x, int y) {
    for (int i = 0; i < spp; ++i) {
      const Sample s = MakeSample(y * w + x, i);
      film.AddSample(x, y, s.rgb, s.laser);
    }
  };
  Film serial(Options(w, h, 3)), parallel(Options(w, h, 3));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) render_pixel(serial, x, y);
  }
  tbb::parallel_for(tbb::blocked_range2d<int>(0, h, 8, 0, w, 8), [&](const tbb::blocked_range2d<int>& tile) {
    for (int y = tile.rows().begin(); y < tile.rows().end(); ++y) {
      for (int x = tile.cols().begin(); x < tile.cols().end(); ++x) render_pixel(parallel, x, y);
    }
  });
  auto same = [](const Image<float>& a, const Image<float>& b) {
    return a.pixels.size() == b.pixels.size() &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
  };
  EXPECT_TRUE(same(serial.RgbImage(), parallel.RgbImage()));
  EXPECT_TRUE(same(serial.LaserImage(), parallel.LaserImage()));
  EXPECT_EQ(serial.DominantSheetImage().pixels, parallel.DominantSheetImage().pixels);
  for (int y = 0; y < h; y += 7) {
    for (int x = 0; x < w; x += 5) EXPECT_EQ(serial.Variance(x, y), parallel.Variance(x, y));
  }
  parallel.Clear();
  EXPECT_EQ(parallel.SampleCount(5, 5), 0u);
  EXPECT_EQ(parallel.MeanRgb(5, 5), Vector3f::Zero());
}

TEST(Film, BadOptions) {
  try {
    Film film(Options(0, 10, 1));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "film: image size must be at least 1 x 1, got 0 x 10");
  }
  EXPECT_THROW(Options(4, 4, -1).Check("x"), InputError);
  FilmOptions o = Options(4, 4, 1);
  o.laser_weight = NAN;
  EXPECT_THROW(o.Check("x"), InputError);
}

}  // namespace
}  // namespace lt
