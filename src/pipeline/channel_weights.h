// The colour channels a stripe is extracted from: the weights of R, G and B
// that give the laser's stripe the best signal-to-noise ratio, from the rig's
// laser wavelengths and the image sensor's quantum efficiency per channel
// (docs/extraction.md, "Colour frames: the laser's channels").
#pragma once

#include <string>
#include <vector>

#include "pipeline/run_folder_reader.h"

namespace lt {

struct LaserChannelWeights {
  // R, G, B weights summing to 1; empty when the rig cannot say (`missing`).
  std::vector<double> weights;
  // Summed over the lasers: each channel's quantum efficiency at the laser's wavelength.
  std::vector<double> response;
  std::vector<double> wavelengths_m;  // the lasers' wavelengths
  // The stripe level the weights are matched at: photo-electrons in the most
  // responsive channel (0: the noise floor alone, the rig gives no noise figures).
  double reference_e = 0;
  std::string missing;  // why there are no weights ("gives no wavelength_nm for laser 0", ...)

  // "R 0.390, G 0.359, B 0.251 (quantum efficiency 0.5, 0.2, 0.05 at 650 nm; ...)"
  std::string Describe() const;
};

// The weights of the demosaiced R, G, B that maximise the signal-to-noise ratio
// of the rig's laser stripe. A pixel of colour c reads n_c = QE_c(lambda) n
// photo-electrons of the stripe, and the sensor model's variance
//   V_c = sigma_d^2 + 1 / (12 K^2) + n_c      [e-^2]
// (dark noise, quantisation, the stripe's own shot noise; the floor is the same
// for every colour: one dark noise, one gain). The demosaiced channel c is the
// mean of the N_c pixels of that colour in each 2x2 tile of the mosaic (green:
// 2), so its variance is V_c / N_c, and the channels come from disjoint pixels
// (independent noise). The weighted sum's SNR, sum(w_c n_c) / sqrt(sum(w_c^2
// V_c / N_c)), is largest for w_c proportional to N_c n_c / V_c
// (Cauchy-Schwarz): N_c QE_c where the floor dominates; N_c (every
// photo-electron counting the same) where shot noise does. The weights are
// matched at the faintest stripe the default threshold keeps: its most
// responsive channel at 10% of the ADC's range (reference_e); without the rig's
// gain, dark noise and bit depth, at the floor. Several lasers: their responses
// are summed. The weights sum to 1, so the weighted image keeps the raw frame's
// full scale and black level. A mono sensor, or a rig without the lasers'
// wavelengths or the sensor's table, gives no weights.
LaserChannelWeights MatchedChannelWeights(const RunRig& rig);

}  // namespace lt
