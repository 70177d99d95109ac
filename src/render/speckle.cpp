#include "render/speckle.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <unsupported/Eigen/FFT>
#include <vector>

#include "core/error.h"
#include "core/random.h"

namespace lt {
namespace {

using Complex = std::complex<float>;

constexpr int64_t kMaxGridPoints = int64_t(1) << 27;

// Smallest n >= m whose prime factors are 2, 3 and 5 (fast FFT sizes).
int NiceFftSize(int m) {
  for (int n = std::max(m, 1);; ++n) {
    int r = n;
    for (int p : {2, 3, 5}) {
      while (r % p == 0) r /= p;
    }
    if (r == 1) return n;
  }
}

// In-place 2D FFT of a row-major nx x ny grid (rows, then columns), forward or
// inverse (Eigen scales the inverse by 1/n). Rows and columns are independent,
// so they run in parallel; each transform is the same whatever the scheduling.
void Fft2d(std::vector<Complex>& grid, int nx, int ny, bool inverse) {
  tbb::parallel_for(tbb::blocked_range<int>(0, ny, 16), [&](const tbb::blocked_range<int>& rows) {
    Eigen::FFT<float> fft;
    std::vector<Complex> in(nx), out(nx);
    for (int y = rows.begin(); y < rows.end(); ++y) {
      std::copy_n(grid.begin() + ptrdiff_t(y) * nx, nx, in.begin());
      inverse ? fft.inv(out, in) : fft.fwd(out, in);
      std::copy_n(out.begin(), nx, grid.begin() + ptrdiff_t(y) * nx);
    }
  });
  tbb::parallel_for(tbb::blocked_range<int>(0, nx, 16), [&](const tbb::blocked_range<int>& cols) {
    Eigen::FFT<float> fft;
    std::vector<Complex> in(ny), out(ny);
    for (int x = cols.begin(); x < cols.end(); ++x) {
      for (int y = 0; y < ny; ++y) in[y] = grid[ptrdiff_t(y) * nx + x];
      inverse ? fft.inv(out, in) : fft.fwd(out, in);
      for (int y = 0; y < ny; ++y) grid[ptrdiff_t(y) * nx + x] = out[y];
    }
  });
}

// Frequency of FFT bin q on an n-point grid, in cycles per sample.
double BinFrequency(int q, int n) { return double(q < (n + 1) / 2 ? q : q - n) / n; }

double Sinc(double x) {
  if (std::abs(x) < 1e-8) return 1.0;
  return std::sin(M_PI * x) / (M_PI * x);
}

// Samples per pixel along each axis. Pixel integration filters the intensity,
// whose band limit 2 nu_c = 1/(lambda N) must then be Nyquist-sampled (spacing
// p/k <= lambda N / 2). Point samples only need the field itself representable
// (band limit nu_c: spacing <= lambda N); the intensity at the samples is exact.
int Subsamples(const SpeckleOptions& o) {
  const double ratio = o.pixel_pitch / (o.wavelength * o.f_number);
  return std::max(1, int(std::ceil((o.integrate_pixels ? 2.0 : 1.0) * ratio - 1e-9)));
}

// 8-point Gauss–Legendre rule on [-1, 1].
constexpr double kGaussX[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
constexpr double kGaussW[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

// Nodes and weights of a composite Gauss–Legendre rule for the triangle
// weight (1 - |a|) on [-1, 1], `panels` panels on each side of the kink at 0.
void TriangleRule(int panels, std::vector<double>* x, std::vector<double>* w) {
  const double h = 1.0 / panels;
  for (int side : {-1, 1}) {
    for (int k = 0; k < panels; ++k) {
      const double mid = (k + 0.5) * h;
      for (int g = 0; g < 4; ++g) {
        for (int s : {-1, 1}) {
          const double a = mid + s * kGaussX[g] * 0.5 * h;
          x->push_back(side * a);
          w->push_back(kGaussW[g] * 0.5 * h * (1.0 - a));
        }
      }
    }
  }
}

}  // namespace

void SpeckleOptions::Check(const std::string& where) const {
  auto positive = [&](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) {
      throw InputError(where, std::string(name) + " must be > 0, got " + FormatNumber(v));
    }
  };
  positive(wavelength, "wavelength");
  positive(f_number, "f_number");
  positive(pixel_pitch, "pixel_pitch");
  if (!(contrast >= 0.0 && contrast <= 1.0)) {
    throw InputError(where, "contrast must be in [0, 1], got " + FormatNumber(contrast));
  }
}

double SpeckleIntensityCorrelation(double r, double wavelength, double f_number) {
  const double v = M_PI * std::abs(r) / (wavelength * f_number);
  if (v < 1e-6) return 1.0 - v * v / 4.0;  // [2 J1(v)/v]^2 = 1 - v^2/4 + O(v^4)
  const double a = 2.0 * std::cyl_bessel_j(1.0, v) / v;
  return a * a;
}

double SpeckleGrainFwhm(double wavelength, double f_number) {
  // [2 J1(v)/v]^2 decreases from 1 to 0 on [0, 3.83]: bisect for 1/2.
  double lo = 0.0, hi = 3.8;
  for (int i = 0; i < 80; ++i) {
    const double mid = 0.5 * (lo + hi);
    const double a = 2.0 * std::cyl_bessel_j(1.0, mid) / mid;
    (a * a > 0.5 ? lo : hi) = mid;
  }
  return 2.0 * lo * wavelength * f_number / M_PI;
}

double SpeckleExpectedCovariance(const SpeckleOptions& o, int dx, int dy) {
  const double c2 = o.contrast * o.contrast;
  const double p = o.pixel_pitch;
  if (!o.integrate_pixels) {
    return c2 * SpeckleIntensityCorrelation(p * std::hypot(double(dx), double(dy)), o.wavelength, o.f_number);
  }
  // C^2 integral over [-1,1]^2 of (1-|a|)(1-|b|) c_I(p |(dx + a, dy + b)|) da db:
  // c_I oscillates with period ~ lambda N / p in a, hence the panel count.
  const int panels = std::max(2, int(std::ceil(4.0 * p / (o.wavelength * o.f_number))));
  std::vector<double> x, w;
  TriangleRule(panels, &x, &w);
  double sum = 0.0;
  for (size_t i = 0; i < x.size(); ++i) {
    for (size_t j = 0; j < x.size(); ++j) {
      const double r = p * std::hypot(dx + x[i], dy + x[j]);
      sum += w[i] * w[j] * SpeckleIntensityCorrelation(r, o.wavelength, o.f_number);
    }
  }
  return c2 * sum;
}

double SpeckleExpectedContrast(const SpeckleOptions& o) { return std::sqrt(SpeckleExpectedCovariance(o, 0, 0)); }

Image<float> GenerateSpeckle(int width, int height, const SpeckleOptions& o, uint64_t key) {
  o.Check("speckle");
  if (width < 0 || height < 0) throw InputError("speckle", "image size must be >= 0");
  Image<float> out(width, height, 1, 1.0f);
  if (width == 0 || height == 0) return out;

  const int k = Subsamples(o);
  const double grain_px = o.wavelength * o.f_number / o.pixel_pitch;  // lambda N in pixels
  const int pad = int(std::ceil(8.0 * grain_px * k)) + 2;
  const int nx = NiceFftSize(k * width + pad), ny = NiceFftSize(k * height + pad);
  if (int64_t(nx) * ny > kMaxGridPoints) {
    throw InputError("speckle", "the speckle grid (" + std::to_string(nx) + " x " + std::to_string(ny) +
                                    " samples) is too large: the grains are much smaller than the pixels; use "
                                    "point samples or a smaller image");
  }

  // Spectrum: circular complex Gaussian inside the pupil |f| <= nu_c, in
  // cycles per grid sample (pixel pitch / k).
  const double nu = o.pixel_pitch / (2.0 * o.wavelength * o.f_number * k);
  std::vector<Complex> grid(size_t(nx) * ny, Complex(0.0f, 0.0f));
  Rng rng(key);
  for (int qy = 0; qy < ny; ++qy) {
    const double fy = BinFrequency(qy, ny);
    if (std::abs(fy) > nu) continue;
    for (int qx = 0; qx < nx; ++qx) {
      const double fx = BinFrequency(qx, nx);
      if (fx * fx + fy * fy > nu * nu) continue;
      const float re = float(rng.NextGaussian()), im = float(rng.NextGaussian());
      grid[size_t(qy) * nx + qx] = Complex(re, im);
    }
  }
  Fft2d(grid, nx, ny, /*inverse=*/true);
  for (Complex& c : grid) c = Complex(std::norm(c), 0.0f);  // intensity |E|^2

  if (o.integrate_pixels && k > 1) {
    // Average over the pixel area: a box of k x k samples, whose transfer
    // function is sinc(f k) per axis.
    Fft2d(grid, nx, ny, /*inverse=*/false);
    std::vector<float> sx(nx), sy(ny);
    for (int q = 0; q < nx; ++q) sx[q] = float(Sinc(BinFrequency(q, nx) * k));
    for (int q = 0; q < ny; ++q) sy[q] = float(Sinc(BinFrequency(q, ny) * k));
    for (int qy = 0; qy < ny; ++qy) {
      for (int qx = 0; qx < nx; ++qx) grid[size_t(qy) * nx + qx] *= sx[qx] * sy[qy];
    }
    Fft2d(grid, nx, ny, /*inverse=*/true);
  }

  // Pixel centres on every k-th sample, normalised to mean 1, blended by C.
  const int off = pad / 2;
  double sum = 0.0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const float v = std::max(0.0f, grid[size_t(off + y * k) * nx + (off + x * k)].real());
      out.At(x, y) = v;
      sum += v;
    }
  }
  const double mean = sum / (double(width) * height);
  const float scale = mean > 0.0 ? float(1.0 / mean) : 0.0f;
  const float c = float(o.contrast);
  for (float& v : out.pixels) v = mean > 0.0 ? 1.0f + c * (v * scale - 1.0f) : 1.0f;
  return out;
}

}  // namespace lt
