#include "pipeline/synthetic_stripes.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/random.h"

namespace lt {

namespace {

constexpr double kSqrtHalfPi = 1.2533141373155002512;  // sqrt(pi / 2)

// First and second antiderivatives of exp(-z^2 / (2 s^2)).
double F1(double z, double s) { return s * kSqrtHalfPi * std::erf(z / (s * M_SQRT2)); }
double F2(double z, double s) {
  return s * kSqrtHalfPi * z * std::erf(z / (s * M_SQRT2)) + s * s * std::exp(-0.5 * z * z / (s * s));
}

// Integral of exp(-(a x + b y + c)^2 / (2 s^2)) over [x0, x1] x [y0, y1], (a, b) a unit vector.
double SquareIntegral(double a, double b, double c, double s, double x0, double x1, double y0, double y1) {
  auto z = [&](double x, double y) { return a * x + b * y + c; };
  constexpr double kEps = 1e-5;
  if (std::abs(b) < kEps) {  // z depends on x only
    const double ym = 0.5 * (y0 + y1);
    return (y1 - y0) * (F1(z(x1, ym), s) - F1(z(x0, ym), s)) / a;
  }
  if (std::abs(a) < kEps) {
    const double xm = 0.5 * (x0 + x1);
    return (x1 - x0) * (F1(z(xm, y1), s) - F1(z(xm, y0), s)) / b;
  }
  return (F2(z(x1, y1), s) - F2(z(x0, y1), s) - F2(z(x1, y0), s) + F2(z(x0, y0), s)) / (a * b);
}

}  // namespace

double SyntheticStripe::CentreU(double v) const {
  if (shape == Shape::kLine) return u0 + std::tan(angle_rad) * (v - v0);
  const double dy = v - cv, q = radius * radius - dy * dy;
  if (q < 0) return std::numeric_limits<double>::quiet_NaN();
  return left_branch ? cu - std::sqrt(q) : cu + std::sqrt(q);
}

double SyntheticStripe::CentreV(double u) const {
  if (shape != Shape::kLine || std::abs(std::tan(angle_rad)) < 1e-12) return std::numeric_limits<double>::quiet_NaN();
  return v0 + (u - u0) / std::tan(angle_rad);
}

double SyntheticStripe::Distance(double x, double y, double* nx, double* ny) const {
  if (shape == Shape::kLine) {
    *nx = std::cos(angle_rad);
    *ny = -std::sin(angle_rad);
    return *nx * (x - u0) + *ny * (y - v0);
  }
  const double dx = x - cu, dy = y - cv, r = std::hypot(dx, dy);
  if (r == 0) {
    *nx = 1, *ny = 0;
    return -radius;
  }
  *nx = dx / r, *ny = dy / r;
  return r - radius;
}

bool SyntheticStripe::VisibleInRow(int v) const {
  if (visible_rows.empty()) return true;
  for (auto [a, b] : visible_rows) {
    if (v >= a && v < b) return true;
  }
  return false;
}

Image<float> RenderSyntheticFrame(const SyntheticFrame& frame) {
  Image<float> img(frame.width, frame.height, 1, float(frame.background));
  for (const SyntheticStripe& st : frame.stripes) {
    const double s = st.sigma, reach = 7.0 * s + 2.0;
    for (int y = 0; y < frame.height; ++y) {
      if (!st.VisibleInRow(y)) continue;
      // Columns near the line in this row.
      int xa = 0, xb = frame.width - 1;
      if (st.shape == SyntheticStripe::Shape::kLine) {
        const double c = st.CentreU(y), half = reach / std::cos(st.angle_rad) + 1.0;
        xa = std::max(0, int(std::floor(c - half)));
        xb = std::min(frame.width - 1, int(std::ceil(c + half)));
      }
      for (int x = xa; x <= xb; ++x) {
        double nx, ny;
        if (std::abs(st.Distance(x, y, &nx, &ny)) > reach) continue;
        double sum = 0;
        if (st.shape == SyntheticStripe::Shape::kLine) {
          const double c = -(nx * st.u0 + ny * st.v0);
          sum = SquareIntegral(nx, ny, c, s, x - 0.5, x + 0.5, y - 0.5, y + 0.5);
        } else {
          constexpr int kSub = 4;
          for (int j = 0; j < kSub; ++j) {
            for (int i = 0; i < kSub; ++i) {
              const double x0 = x - 0.5 + double(i) / kSub, y0 = y - 0.5 + double(j) / kSub;
              const double xm = x0 + 0.5 / kSub, ym = y0 + 0.5 / kSub;
              double mx, my;
              const double d = st.Distance(xm, ym, &mx, &my);
              const double c = d - (mx * xm + my * ym);  // locally straight: d(p) ~ m . p + c
              sum += SquareIntegral(mx, my, c, s, x0, x0 + 1.0 / kSub, y0, y0 + 1.0 / kSub);
            }
          }
        }
        img.At(x, y) += float(st.amplitude * sum);
      }
    }
  }
  if (frame.noise_sigma > 0) {
    for (int y = 0; y < frame.height; ++y) {
      for (int x = 0; x < frame.width; ++x) {
        Rng rng = Rng::For(frame.seed, 0, uint64_t(y) * frame.width + x, 0, 0x5717);
        img.At(x, y) += float(frame.noise_sigma * rng.NextGaussian());
      }
    }
  }
  return img;
}

template <typename T>
Image<T> QuantizeImage(const Image<float>& image) {
  Image<T> out(image.width, image.height, image.channels);
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    if constexpr (std::is_integral_v<T>) {
      const double v = std::round(double(image.pixels[i]));
      out.pixels[i] = T(std::clamp(v, 0.0, double(std::numeric_limits<T>::max())));
    } else {
      out.pixels[i] = image.pixels[i];
    }
  }
  return out;
}

template Image<uint8_t> QuantizeImage<uint8_t>(const Image<float>&);
template Image<uint16_t> QuantizeImage<uint16_t>(const Image<float>&);
template Image<float> QuantizeImage<float>(const Image<float>&);

}  // namespace lt
