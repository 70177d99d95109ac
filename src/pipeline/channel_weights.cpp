#include "pipeline/channel_weights.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sensor/image_sensor.h"

namespace lt {

namespace {

std::string Number(double v, const char* format = "%.3g") {
  char buf[32];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

}  // namespace

std::string LaserChannelWeights::Describe() const {
  if (weights.size() != 3) return "none (" + missing + ")";
  static const char* const kNames[] = {"R", "G", "B"};
  std::string text;
  for (int c = 0; c < 3; ++c) text += std::string(c ? ", " : "") + kNames[c] + " " + Number(weights[size_t(c)], "%.3f");
  text += " (quantum efficiency ";
  for (int c = 0; c < 3; ++c) text += (c ? ", " : "") + Number(response[size_t(c)]);
  text += " at ";
  for (size_t i = 0; i < wavelengths_m.size(); ++i) text += (i ? " + " : "") + Number(wavelengths_m[i] * 1e9, "%.0f");
  text += " nm; ";
  text += reference_e > 0 ? "matched at a stripe of " + Number(reference_e, "%.0f") +
                                " e- in its best channel, the default threshold"
                          : "the rig gives no gain, dark noise and bit depth: matched at the noise floor";
  return text + ")";
}

LaserChannelWeights MatchedChannelWeights(const RunRig& rig) {
  LaserChannelWeights out;
  const std::string source = rig.source.filename().string();
  if (rig.laser_wavelength_m.empty()) {
    out.missing = source + " describes no laser";
    return out;
  }
  for (size_t i = 0; i < rig.laser_wavelength_m.size(); ++i) {
    if (!(rig.laser_wavelength_m[i] > 0)) {
      out.missing = source + " gives no wavelength_nm for laser " + std::to_string(i);
      return out;
    }
  }
  if (rig.color_filter == ColorFilter::kMono) {
    out.missing = source + "'s image sensor is mono (color_filter): no quantum efficiency per colour channel";
    return out;
  }
  if (rig.qe_wavelength_m.empty()) {
    out.missing = source + " gives no image_sensor.quantum_efficiency per colour channel";
    return out;
  }
  // The sensor model's own interpolation of the table (linear, constant beyond its ends).
  ImageSensorParams p;
  p.color_filter = rig.color_filter;
  p.qe_wavelength_m = rig.qe_wavelength_m;
  p.qe = rig.qe;
  const ImageSensor sensor(p);
  out.response.assign(3, 0.0);
  for (double wavelength : rig.laser_wavelength_m) {
    out.wavelengths_m.push_back(wavelength);
    for (int c = 0; c < 3; ++c) out.response[size_t(c)] += sensor.QuantumEfficiency(c, wavelength);
  }
  const double best = std::max({out.response[0], out.response[1], out.response[2]});
  if (!(best > 0)) {
    out.missing = source + ": the quantum efficiency is 0 in every channel at the lasers' wavelengths";
    return out;
  }
  // Noise floor and the reference stripe, in electrons.
  double floor = 1, reference = 0;
  const double K = rig.system_gain_dn_per_e;
  if (K > 0 && rig.dark_noise_e >= 0 && rig.bit_depth > 0) {
    floor = rig.dark_noise_e * rig.dark_noise_e + 1.0 / (12.0 * K * K);
    reference = 0.1 * (std::ldexp(1.0, rig.bit_depth) - 1.0) / K;
  }
  out.reference_e = reference;
  // Pixels of each colour in the mosaic's 2x2 tile: a demosaiced channel is
  // the mean of that many samples per tile (green: 2).
  double tile[3] = {0, 0, 0};
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x) tile[FilterChannel(rig.color_filter, x, y)] += 1;
  std::vector<double> w(3);
  double sum = 0;
  for (int c = 0; c < 3; ++c) {
    const double n = out.response[size_t(c)] / best * reference;
    w[size_t(c)] = tile[c] * out.response[size_t(c)] / (floor + n);
    sum += w[size_t(c)];
  }
  for (double v : w) out.weights.push_back(v / sum);
  return out;
}

}  // namespace lt
