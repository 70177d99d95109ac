// Colour at a single wavelength. Materials hold linear RGB; monochromatic light
// (a laser, a pattern projector) needs the reflectance at its wavelength. The
// RGB triple is read as samples of a smooth spectrum at the broadband bands'
// representative wavelengths (B 465 nm, G 540 nm, R 610 nm, the image sensor's
// defaults), linearly interpolated between them and held constant beyond.
#pragma once

#include <Eigen/Core>

namespace lt {

inline constexpr double kBandWavelengthB = 465e-9;
inline constexpr double kBandWavelengthG = 540e-9;
inline constexpr double kBandWavelengthR = 610e-9;

inline float ValueAtWavelength(const Eigen::Vector3f& rgb, double wavelength_m) {
  if (wavelength_m <= kBandWavelengthB) return rgb.z();
  if (wavelength_m >= kBandWavelengthR) return rgb.x();
  if (wavelength_m <= kBandWavelengthG) {
    float t = float((wavelength_m - kBandWavelengthB) / (kBandWavelengthG - kBandWavelengthB));
    return rgb.z() + t * (rgb.y() - rgb.z());
  }
  float t = float((wavelength_m - kBandWavelengthG) / (kBandWavelengthR - kBandWavelengthG));
  return rgb.y() + t * (rgb.x() - rgb.y());
}

inline double ValueAtWavelength(const Eigen::Vector3d& rgb, double wavelength_m) {
  return double(ValueAtWavelength(Eigen::Vector3f(rgb.cast<float>()), wavelength_m));
}

}  // namespace lt
