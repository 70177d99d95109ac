// DetectCheckerboard (pipeline/calib_corners.h): the image averaged to one
// channel and its noise, the requested scale, then the ladder of other scales
// with the checks on a board found at one of them. The detection at one scale
// is in calib_corner_at_scale.cpp, its candidate corners and their tests in
// calib_corner_candidates.cpp, the grid in calib_corner_grid.cpp.
#include "pipeline/calib_corners.h"

#include <algorithm>
#include <optional>
#include <cmath>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "core/error.h"
#include "pipeline/calib_corner_at_scale.h"
#include "pipeline/calib_corner_candidates.h"
#include "pipeline/calib_corner_grid.h"
#include "pipeline/gaussian_filter.h"
#include "pipeline/option_checks.h"

namespace lt {

using corner_detail::DetectAtScale;
using corner_detail::Failure;
using corner_detail::kMaxAsymmetry;
using corner_detail::NoiseSigma;
using corner_detail::ContrastFloor;
using corner_detail::GridPrediction;
using corner_detail::OffGrid;
using corner_detail::PointAsymmetry;
using corner_detail::SaddleAtScale;
using corner_detail::RefineSaddle;
using corner_detail::SaddleNear;
using corner_detail::SaddleStdPx;
using corner_detail::ScaleResult;

namespace {

template <typename T>
Image<float> ToFloat(const ImageView<T>& v) {
  Image<float> out(v.width, v.height, 1);
  for (int y = 0; y < v.height; ++y) {
    for (int x = 0; x < v.width; ++x) {
      double s = 0;
      for (int c = 0; c < v.channels; ++c) s += double(v.At(x, y, c));
      out.At(x, y) = float(s / v.channels);
    }
  }
  return out;
}

// Scales to try after the requested one failed for a reason another scale
// may cure: twice and three times it (blur, large squares), then 1/1.5 and
// 1/2.25 of it (small or foreshortened squares), within [0.7, 5]; values
// within 10% of one already on the ladder are left out.
std::vector<double> ScaleLadder(double sigma) {
  std::vector<double> ladder{sigma};
  for (double f : {2.0, 3.0, 1 / 1.5, 1 / 2.25}) {
    const double s = std::clamp(sigma * f, 0.7, 5.0);
    bool near = false;
    for (double o : ladder) near = near || std::abs(s - o) < 0.1 * o;
    if (!near) ladder.push_back(s);
  }
  ladder.erase(ladder.begin());
  return ladder;
}

// How far corner (i, j) may lie from where the homography through its
// neighbours puts it: 0.35 px and 6 predicted standard deviations (model and
// noise), and a tenth of the local spacing (the lens bends the grid in
// proportion to its size). A point farther off is another feature.
double OffGridTolerance(const CornerDetection& d, const CheckerboardSpec& board, int i, int j,
                        const Eigen::Vector2d& at) {
  double spacing = 0;
  int n = 0;
  for (const auto& [a, b] : {std::pair{i - 1, j}, std::pair{i + 1, j}, std::pair{i, j - 1}, std::pair{i, j + 1}}) {
    if (a < 0 || b < 0 || a >= board.rows || b >= board.cols) continue;
    spacing += (d.corners[size_t(a * board.cols + b)] - at).norm();
    ++n;
  }
  return std::max(0.35 + 6 * d.corner_std_px[size_t(i * board.cols + j)], 0.1 * spacing / std::max(n, 1));
}

// Every corner of a complete board where its neighbours put it. The grid
// takes the nearest candidate within neighbour_tolerance of the spacing of
// its prediction: where the corner itself is no candidate (its saddle lost,
// a saddle of noise in a square of a JPEG beside it) another point up to
// that far off may take its place, and the whole view would then pull the
// calibration. Such corners are looked for again by Newton's method from
// their predictions, the farthest off first, until none is left; where two
// wrong corners lie side by side the prediction of the farther may be pulled
// off by the other, so when its saddle is not found the next is tried (its
// replacement then corrects the first's prediction). A saddle found there
// replaces the corner when the homography through its neighbours puts it
// within the tolerance. Two wrong corners side by side each pull the other's
// prediction off, so that neither qualifies: when no corner does, each is
// predicted again from its neighbours that lie within the tolerance, and
// the first whose saddle found there at least halves its distance from
// that prediction is replaced. The loop ends only with every corner within the
// tolerance; when no off-grid corner's saddle is found at its prediction the
// board is refused, naming the farthest off.
bool CornersOnGrid(const Image<float>& img, double noise, const ContrastFloor& floor, double sigma,
                   double min_response, const CheckerboardSpec& board, CornerDetection* d) {
  const GaussianKernels kernels(sigma);
  for (int round = 0; round < board.CornerCount(); ++round) {
    std::vector<std::pair<double, int>> off;  // (distance / tolerance, corner index), ratio > 1
    for (int i = 0; i < board.rows; ++i) {
      for (int j = 0; j < board.cols; ++j) {
        const double ratio = OffGrid(d->corners, board.rows, board.cols, i, j) /
                             OffGridTolerance(*d, board, i, j, d->corners[size_t(i * board.cols + j)]);
        if (ratio > 1) off.push_back({ratio, i * board.cols + j});
      }
    }
    if (off.empty()) return true;
    // The farthest off first; equal ratios in board order.
    std::stable_sort(off.begin(), off.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    bool replaced = false;
    std::vector<char> off_grid(d->corners.size(), 0);
    for (const auto& o : off) off_grid[size_t(o.second)] = 1;
    for (int pass = 0; pass < 2 && !replaced; ++pass) {
      for (const auto& [ratio, k] : off) {
        const int i = k / board.cols, j = k % board.cols;
        Eigen::Vector2d predicted, p;
        Eigen::Matrix2d hessian;
        if (!GridPrediction(d->corners, board.rows, board.cols, i, j, &predicted, pass == 0 ? nullptr : &off_grid) ||
            !SaddleNear(img.View(), predicted, sigma, floor, min_response, &p, &hessian) ||
            (p - d->corners[size_t(k)]).norm() < 1e-3) {
          continue;
        }
        std::vector<Eigen::Vector2d> trial = d->corners;
        trial[size_t(k)] = p;
        const double after = OffGrid(trial, board.rows, board.cols, i, j);
        if (pass == 0 ? !(after <= OffGridTolerance(*d, board, i, j, p))
                      : !((p - predicted).norm() <= 0.5 * (d->corners[size_t(k)] - predicted).norm())) {
          continue;
        }
        d->corners[size_t(k)] = p;
        d->corner_std_px[size_t(k)] = SaddleStdPx(kernels, noise, hessian);
        for (GridCorner& g : d->grid) {
          if (g.i == i && g.j == j) g.pixel = p;
        }
        replaced = true;
        break;
      }
    }
    if (!replaced) {
      const int i = off.front().second / board.cols, j = off.front().second % board.cols;
      d->ok = false;
      d->reason = "corner (" + std::to_string(i) + ", " + std::to_string(j) + ") of the grid lies " +
                  Fmt(OffGrid(d->corners, board.rows, board.cols, i, j)) +
                  " px from where its neighbours put it, and no corner was found there";
      d->corners.clear();
      d->corner_std_px.clear();
      return false;
    }
  }
  return true;
}

// The image halved in each direction, each pixel the mean of a 2 x 2 block
// (an odd last row or column dropped): half-image pixel (x, y) is centred on
// full-image point (2x + 0.5, 2y + 0.5).
Image<float> Halved(const Image<float>& img) {
  Image<float> h(img.width / 2, img.height / 2, 1);
  for (int y = 0; y < h.height; ++y)
    for (int x = 0; x < h.width; ++x)
      h.At(x, y) = 0.25f * (img.At(2 * x, 2 * y) + img.At(2 * x + 1, 2 * y) + img.At(2 * x, 2 * y + 1) +
                            img.At(2 * x + 1, 2 * y + 1));
  return h;
}

// The board found on the image halved (recursively, while the image keeps at
// least 128 px a side), its corners refined on this image by Newton's method
// at twice the scale they were found at, from twice their position plus half
// a pixel; their standard deviations from this image's noise at that scale.
// nullopt when not found, or when a corner's saddle is not within 2 px here.
std::optional<CornerDetection> DetectOnHalfImage(const Image<float>& img, double noise,
                                                 const CheckerboardSpec& board, const CornerDetectionOptions& options) {
  if (std::min(img.width, img.height) < 256) return std::nullopt;
  const Image<float> half = Halved(img);
  CornerDetection d = DetectCheckerboard(half.View(), board, options);
  if (!d.ok) return std::nullopt;
  const double sigma = 2 * d.sigma_px;
  const GaussianKernels kernels(sigma);
  for (size_t k = 0; k < d.corners.size(); ++k) {
    Eigen::Vector2d p = 2.0 * d.corners[k] + Eigen::Vector2d(0.5, 0.5);
    Eigen::Matrix2d hessian;
    if (!RefineSaddle(img.View(), sigma, kernels.radius, 2 * sigma + 2, &p, &hessian)) return std::nullopt;
    d.corners[k] = p;
    d.corner_std_px[k] = SaddleStdPx(kernels, noise, hessian);
  }
  for (GridCorner& g : d.grid) g.pixel = d.corners[size_t(g.i * board.cols + g.j)];
  d.sigma_px = sigma;
  d.noise_sigma = noise;
  ++d.other_scales_tried;
  return d;
}

}  // namespace

void CornerDetectionOptions::Check() const {
  Require(std::isfinite(sigma_px) && sigma_px >= 0.7 && sigma_px <= 5, "sigma_px",
          "must be in [0.7, 5] pixels, got " + FormatNumber(sigma_px));
  Require(min_response > 0 && min_response < 1, "min_response", "must be in (0, 1), got " + FormatNumber(min_response));
  Require(neighbour_tolerance > 0 && neighbour_tolerance < 0.5, "neighbour_tolerance",
          "must be in (0, 0.5), got " + FormatNumber(neighbour_tolerance));
  Require(max_seeds >= 1, "max_seeds", "must be >= 1, got " + std::to_string(max_seeds));
}

template <typename T>
CornerDetection DetectCheckerboard(const ImageView<T>& view, const CheckerboardSpec& board,
                                   const CornerDetectionOptions& options) {
  options.Check();
  board.Check();
  if (view.empty() || view.data == nullptr || view.channels < 1) throw InputError("", "empty image");
  const Image<float> img = ToFloat(view);
  double noise = NoiseSigma(img);
  if (std::is_integral_v<T>) noise = std::sqrt(noise * noise + 1.0 / 12.0);  // quantisation
  ScaleResult first = DetectAtScale(img, noise, board, options, options.sigma_px);
  if (first.det.ok &&
      !CornersOnGrid(img, noise, first.floor, options.sigma_px, options.min_response, board, &first.det)) {
    return std::move(first.det);
  }
  if (first.det.ok || !options.other_scales ||
      !(first.failure == Failure::kFewCandidates || first.failure == Failure::kNoGrid ||
        first.failure == Failure::kIncompleteGrid)) {
    return std::move(first.det);
  }
  // Another scale: the first complete grid whose order the colours confirm.
  std::string tried;
  for (double s : ScaleLadder(options.sigma_px)) {
    ScaleResult r = DetectAtScale(img, noise, board, options, s);
    ++first.det.other_scales_tried;
    // A larger kernel averages more of the corner's surroundings: where an
    // occluder hides a corner it can still make a saddle there, a pixel or
    // two off. A corner found at a larger scale must therefore be
    // point-symmetric within that scale's validation circle (an occluder
    // beside it is not) and a saddle at the requested scale too, at the
    // same place. (A smaller kernel sees less than the requested one: it
    // cannot make corners out of an occluder's surroundings.)
    // Any other scale: each corner where the homography through its
    // neighbours puts it, and a saddle about as sharp as theirs (a corner
    // made of an occluder's edges is off, and weak: its predicted standard
    // deviation at most twice the median of its neighbours').
    for (int i = 0; r.det.ok && i < board.rows; ++i) {
      for (int j = 0; r.det.ok && j < board.cols; ++j) {
        const double std_px = r.det.corner_std_px[size_t(i * board.cols + j)];
        std::vector<double> around;
        for (int a = std::max(0, i - 1); a <= std::min(board.rows - 1, i + 1); ++a)
          for (int b = std::max(0, j - 1); b <= std::min(board.cols - 1, j + 1); ++b)
            if (a != i || b != j) around.push_back(r.det.corner_std_px[size_t(a * board.cols + b)]);
        std::nth_element(around.begin(), around.begin() + ptrdiff_t(around.size() / 2), around.end());
        if (!(std_px <= 2 * around[around.size() / 2])) r.det.ok = false;
        if (!(OffGrid(r.det.corners, board.rows, board.cols, i, j) <= 0.35 + 6 * std_px)) r.det.ok = false;
      }
    }
    if (r.det.ok && s > options.sigma_px) {
      for (size_t k = 0; r.det.ok && k < r.det.corners.size(); ++k) {
        if (!(PointAsymmetry(img, r.det.corners[k], 2.5 * s + 1, noise) <= kMaxAsymmetry) ||
            !SaddleAtScale(img.View(), r.det.corners[k], r.det.corner_std_px[k], options.sigma_px, s, noise, first.floor,
                           options.min_response)) {
          r.det.ok = false;
        }
      }
    }
    if (r.det.ok) {
      r.det.other_scales_tried = first.det.other_scales_tried;
      return std::move(r.det);
    }
    tried += (tried.empty() ? "" : ", ") + Fmt(s);
  }
  first.det.reason += " (also refused at sigma_px = " + tried + ")";
  // A board blurred beyond the ladder's largest scale (a large photograph out
  // of focus): found on the image halved, then each corner refined here.
  if (std::optional<CornerDetection> half = DetectOnHalfImage(img, noise, board, options)) {
    half->other_scales_tried += first.det.other_scales_tried;
    return std::move(*half);
  }
  return std::move(first.det);
}

template CornerDetection DetectCheckerboard<uint8_t>(const ImageView<uint8_t>&, const CheckerboardSpec&,
                                                     const CornerDetectionOptions&);
template CornerDetection DetectCheckerboard<uint16_t>(const ImageView<uint16_t>&, const CheckerboardSpec&,
                                                      const CornerDetectionOptions&);
template CornerDetection DetectCheckerboard<float>(const ImageView<float>&, const CheckerboardSpec&,
                                                   const CornerDetectionOptions&);

CornerDetection DetectCheckerboard(const AnyImage& image, const CheckerboardSpec& board,
                                   const CornerDetectionOptions& options) {
  return std::visit([&](const auto& img) { return DetectCheckerboard(img.View(), board, options); }, image);
}

CalibrationView ViewOfDetection(const CheckerboardSpec& board, const CornerDetection& detection) {
  return {board.CornerPoints(), detection.corners};
}

}  // namespace lt
