// Internal to checkerboard corner detection (pipeline/calib_corners.cpp and the
// pipeline/calib_corner_*.cpp files that hold its parts), not an API: use
// DetectCheckerboard (pipeline/calib_corners.h).
// The candidate corners and their tests: the image's noise, the smoothed image
// with its second derivatives, the saddle point refined to subpixel, the two
// edges through it on a ring, the saddle at a finer scale and the point
// asymmetry about a corner.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <vector>

#include "core/image.h"
#include "pipeline/gaussian_filter.h"

namespace lt {
namespace corner_detail {

// Image noise σ (Immerkær's operator, the median of its magnitude).
double NoiseSigma(const Image<float>& img);

// The smoothed image and its saddle response, whole image (borders mirrored).
struct Smoothed {
  int w = 0, h = 0;
  std::vector<float> r;         // the smoothed image
  std::vector<float> strength;  // the saddle response r_xy² − r_xx·r_yy (its second derivatives are not kept)
  float At(const std::vector<float>& v, int x, int y) const { return v[size_t(y) * size_t(w) + size_t(x)]; }
  // Bilinear sample of r (clamped to the image).
  double Sample(double x, double y) const {
    x = std::clamp(x, 0.0, w - 1.0);
    y = std::clamp(y, 0.0, h - 1.0);
    const int x0 = std::min(int(x), w - 2 < 0 ? 0 : w - 2), y0 = std::min(int(y), h - 2 < 0 ? 0 : h - 2);
    const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
    const double fx = x - x0, fy = y - y0;
    return (1 - fy) * ((1 - fx) * At(r, x0, y0) + fx * At(r, x1, y0)) + fy * ((1 - fx) * At(r, x0, y1) + fx * At(r, x1, y1));
  }
};

// The image smoothed with kernels k, and its saddle response.
Smoothed Smooth(const Image<float>& img, const GaussianKernels& k);

// The contrast a corner must span on its validation circle (and two
// neighbouring squares must differ by to tell their colours): 3 noise σ, and
// a tenth of the light on it, the brighter side's level above the image's
// dark level. A board's black and white squares differ by far more than a
// tenth of the light that falls on them, however dim; faint texture on a
// lit surface does not. (A tenth of the whole image's contrast instead
// refused the corners of a board's dim end where the light fell to a
// twentieth across it, as a lamp beside a wide-angle camera's close board
// does.)
struct ContrastFloor {
  double noise_floor = 0;  // 3 σ_n
  double dark = 0;         // the image's dark level (0.1st percentile of the smoothed image)
  double For(double bright) const { return std::max(noise_floor, 0.1 * (bright - dark)); }
};

struct Candidate {
  Eigen::Vector2d p;
  double strength = 0;
  Eigen::Vector2d e1, e2;  // unit directions of the two edges through the corner
  Eigen::Matrix2d hessian;
};

// The predicted standard deviation per axis of a saddle found on the image
// smoothed with `kernels` (image noise `noise`, Hessian `hessian` there): the
// gradient's noise σ_n² c with c = Σk1² Σk0² through the Newton step,
// Cov = σ_n² c H⁻¹H⁻ᵀ; half its trace.
double SaddleStdPx(const GaussianKernels& kernels, double noise, const Eigen::Matrix2d& hessian);

// Newton's method on the gradient of the smoothed image: the saddle point.
bool RefineSaddle(const ImageView<float>& img, double sigma, int radius, double border, Eigen::Vector2d* p,
                  Eigen::Matrix2d* hessian);

// Four dark/bright changes on a circle around the corner, at two pairs of
// nearly opposite angles: the two edges.
constexpr int kCircleSamples = 48;

// The smoothed image on a circle around p; returns its range (max − min).
double CircleSamples(const Smoothed& s, const Eigen::Vector2d& p, double radius, double* v);
// The two edges through the corner at p (c->e1, c->e2) from the smoothed image
// on the circle of `radius` around it; false unless its range there reaches
// the contrast floor for its brightest value and it changes between dark and
// bright four times, at two pairs of nearly opposite angles.
bool EdgeDirections(const Smoothed& s, const Eigen::Vector2d& p, double radius, const ContrastFloor& floor, Candidate* c);

// The saddle of the image smoothed at `sigma` that Newton's method reaches
// from `start` (within 2 px), with its Hessian: found when it is a saddle of
// at least min_response of the ideal response for the range on its validation
// circle (radius 2.5·sigma + 1), with the X of step 3 there.
bool SaddleNear(const ImageView<float>& img, const Eigen::Vector2d& start, double sigma, const ContrastFloor& floor,
                double min_response, Eigen::Vector2d* p, Eigen::Matrix2d* hessian);

// Whether the image smoothed at `sigma`, smaller than the scale `found_sigma`
// the corner p was found at, has the corner's saddle too, at the same place.
bool SaddleAtScale(const ImageView<float>& img, const Eigen::Vector2d& p, double p_std, double sigma, double found_sigma,
                   double noise, const ContrastFloor& floor, double min_response);

// Point asymmetry of the image about p within radius r: the RMS difference
// between the image at p + d and at p − d, less its expectation from noise
// and a linear light gradient,
// as a fraction of the range of the image there. The four squares around a
// corner (and the ones beyond) are point-symmetric about it, whatever the
// perspective, and so is any symmetric blur of them (defocus, motion):
// blur and noise leave it near 0; an occluder beside the corner does not.
constexpr double kMaxAsymmetry = 0.05;  // measured: up to 0.03 on boards, 0.08 and more beside occluders
double PointAsymmetry(const Image<float>& img, const Eigen::Vector2d& p, double r, double noise);

}  // namespace corner_detail
}  // namespace lt
