// Laser speckle on the image plane: a fully developed speckle pattern as the
// camera's pupil images a rough surface lit by coherent light (Goodman,
// "Speckle Phenomena in Optics", 2007, chapters 3-5).
//
// The field is a circular complex Gaussian random process band-limited by the
// circular exit pupil: its spectrum is white inside |nu| <= nu_c = 1/(2 lambda N)
// (the coherent cut-off of a pupil of working f-number N) and zero outside. Then
//   field correlation      mu_A(r) = 2 J1(v) / v,   v = pi r / (lambda N)
//   intensity covariance   c_I(r) = Cov(I(x), I(x+r)) / <I>^2 = [2 J1(v) / v]^2
// whose full width at half maximum is 1.029 lambda N on the sensor: the mean
// grain size. The intensity |field|^2 has exponential statistics (std/mean = 1).
// A pixel integrates the intensity over its area, which lowers the contrast
// when grains are not much larger than the pixel:
//   C_pix^2 = (1/p^4) integral over [-p, p]^2 of (p - |u|)(p - |v|) c_I(|(u, v)|) du dv.
// The contrast setting C blends the result toward uniform: I' = 1 + C (I - 1),
// so std/mean = C * C_pix (= C for point samples). Method and tests:
// docs/rendering.md, "Laser speckle".
#pragma once

#include <cstdint>
#include <string>

#include "core/image.h"

namespace lt {

struct SpeckleOptions {
  double wavelength = 0.0;   // [m], > 0
  double f_number = 0.0;     // working (image-side) f-number N = 1 / (2 NA'), > 0
  double pixel_pitch = 0.0;  // [m], > 0
  double contrast = 1.0;     // C in [0, 1]
  // Average the intensity over each pixel's area (what a sensor does); false
  // samples it at the pixel centres.
  bool integrate_pixels = true;

  // Throws lt::InputError(where, ...) for out-of-range or non-finite values.
  void Check(const std::string& where) const;
};

// Speckle intensity for a width x height image, mean exactly 1 over the image
// (speckle redistributes light, it does not add or remove it).
//
// Synthesis: the spectrum inside the pupil is filled with complex Gaussian
// numbers drawn from Rng(key) in a fixed order, transformed to the field by
// an inverse FFT (Eigen's FFT) on a grid padded by 8 lambda N on each axis
// (so that the periodic wrap-around leaves the image uncorrelated with its
// opposite edge) and sampled k times per pixel along each axis: with pixel
// integration k >= 2 p / (lambda N), so that the intensity (band limit 2 nu_c)
// is Nyquist-sampled; for point samples k >= p / (lambda N), so that the field
// is. Pixel integration multiplies the intensity's spectrum
// by sinc(f_x p) sinc(f_y p) (exact for a band-limited intensity). Memory: one
// complex float per grid point, about 8 k^2 width height bytes; the grid is
// limited to 2^27 points (InputError beyond). Use key = HashKey(scene seed,
// frame, purpose): the same key gives a bit-identical pattern.
Image<float> GenerateSpeckle(int width, int height, const SpeckleOptions& options, uint64_t key);

// Closed forms (r and lengths in metres).
double SpeckleIntensityCorrelation(double r, double wavelength, double f_number);  // c_I(r)
// Full width at half maximum of c_I: 1.02899 lambda N.
double SpeckleGrainFwhm(double wavelength, double f_number);
// Expected normalised covariance Cov(I_a, I_b) / <I>^2 of two pixels dx, dy
// pixels apart, for the options' pixel model (point samples or pixel areas)
// and contrast C: C^2 c_I for points; C^2 times the double pixel-area average
// of c_I otherwise (numerical quadrature, relative accuracy ~1e-4).
double SpeckleExpectedCovariance(const SpeckleOptions& options, int dx, int dy);
// std/mean of GenerateSpeckle's output: sqrt(SpeckleExpectedCovariance(o, 0, 0)).
double SpeckleExpectedContrast(const SpeckleOptions& options);

}  // namespace lt
