// Colour and laser bleeding for the points of a scan sequence (docs/pipeline.md,
// "Colour"): each point of a dim (laser) frame, in the world frame, is projected
// into the bright frames next to it in the run (the previous and the next frame
// that is neither a laser nor a pattern frame, RunFrame::IsColourFrame, and has a
// pose; laser and pattern frames are passed over), the bright image is sampled there and
// the samples are averaged.
//
// Sampling: bilinear. A colour sensor's raw mosaic is demosaiced at the sample
// point: each colour is interpolated bilinearly from the pixels of that colour
// alone (its own lattice of spacing 2; green from both of its lattices, averaged).
// The colour is the camera's linear raw RGB, (DN - black level) / (full scale -
// black level) scaled to 0..255, without white balance; mono images give grey.
// A point whose projection falls outside a bright image, or behind its camera,
// takes no sample from it; a point with no sample is uncoloured (0, 0, 0).
// Occlusion is not checked: a point hidden from a bright frame's camera by other
// surfaces still takes its colour there (the scanner moves little between the
// frames of a pair, so this is rare; the label of the point says what it lies on).
//
// Laser bleeding: a sample is contaminated when the laser lit the bright frame at
// the sample point. With the bright frame's radiance EXR (rendered runs), when its
// laser radiance there is at least `contamination_ratio` times the mean of its
// broadband R, G, B radiance; without it (captured runs), when the manifest says
// the laser lit part of the bright frame's exposure (lit_fraction.laser > 0). A
// point is contaminated when any of its samples is.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "core/image.h"
#include "pipeline/run_folder_reader.h"
#include "sensor/camera.h"
#include "sensor/image_sensor.h"

namespace lt {

struct ColourOptions {
  double contamination_ratio = 0.05;
  void Check() const;  // throws lt::InputError
};

// Channel values (R, G, B, in the image's units) of an image at subpixel position
// (u, v), bilinear; a mosaic (filter != kMono, one channel) demosaiced as above;
// a mono one-channel image gives the same value three times, a 3-channel image its
// channels. Positions are clamped to the image.
Eigen::Vector3d SampleColour(const Image<float>& image, ColorFilter filter, const Eigen::Vector2d& uv);

struct PointColour {
  std::array<uint8_t, 3> rgb = {0, 0, 0};
  bool coloured = false;      // at least one bright frame sampled
  bool contaminated = false;  // a sample was lit by the laser (see above)
};

struct ColourStats {
  int points = 0;        // points asked about
  int coloured = 0;      // points with a colour
  int contaminated = 0;  // coloured points whose colour the laser contaminated
  bool from_radiance = true;  // every sample's contamination came from a radiance EXR
  int bright_frames = 0;      // bright frames used
};

class Colorizer {
 public:
  // frames: the whole run (sorted by index), to find the bright frames.
  Colorizer(const std::vector<RunFrame>& frames, const Camera& camera, ColorFilter filter, double black_level_dn,
            const ColourOptions& options = {});
  ~Colorizer();
  // Colours of the points of laser frame `frame_index` (world frame).
  std::vector<PointColour> Colour(int frame_index, const std::vector<Eigen::Vector3d>& points_in_world);
  const ColourStats& stats() const { return stats_; }

 private:
  struct Bright;
  const Bright* Load(size_t position);

  std::vector<RunFrame> frames_;
  Camera camera_;
  ColorFilter filter_;
  double black_level_dn_;
  ColourOptions options_;
  std::map<size_t, std::unique_ptr<Bright>> cache_;
  ColourStats stats_;
};

}  // namespace lt
