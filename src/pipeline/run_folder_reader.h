// Reading a run folder for the measurement pipeline: the frame list
// (manifest.jsonl) and the scanner's geometry (rig.json, or scene.json's
// "sensor" section). This reads what `lasertwin render` writes (see
// docs/pipeline.md, "Run folder") but does not depend on the renderer, so a
// capture tool for a real scanner can write the same files.
//
// manifest.jsonl: one JSON object per line. Keys read (others are ignored, so
// the renderer may record more, e.g. render statistics):
//   index            integer >= 0, unique                               required
//   files.image      image file, relative to the run folder             required
//   shutter.laser_on, lit_fraction.laser
//                    a frame is a laser (dim) frame when laser_on is true
//                    or the laser lit part of its exposure; a line with
//                    neither key counts as a laser frame
//   files.centers    ground-truth stripe centres (CSV)                   optional
//   files.gt         ground-truth buffers (EXR: Z, N.X, N.Y, N.Z, instance, ...) optional
//   files.radiance   radiance EXR (R, G, B, laser channels)                optional
//   world_from_cam   camera pose at mid-exposure (core/pose.h forms)     optional
//   world_from_tool  robot tool (flange) pose at mid-exposure            optional
//   gt_axis          "rows" | "cols": how the ground truth was scanned    optional
//   bit_depth        the sensor's ADC bits (1..16)                       optional
//   png_bit_depth    8 | 16                                              optional
//   label, t_start_s, t_end_s                                            optional
// Errors are lt::InputError naming "manifest.jsonl:LINE" (and the JSON pointer).
#pragma once

#include <array>
#include <filesystem>
#include <limits>
#include <type_traits>
#include <optional>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/pose.h"
#include "pipeline/extraction_options.h"
#include "sensor/camera.h"
#include "sensor/image_sensor.h"
#include "sensor/plane.h"

namespace lt {

struct RunFrame {
  int index = 0;
  std::string where;  // "RUN/manifest.jsonl:LINE", for messages about this frame
  std::string label;
  bool laser_on = false;
  double laser_fraction = 0;
  bool shutter_known = false;  // the line has shutter.laser_on or lit_fraction.laser
  bool laser_on_known = false;  // the line has shutter.laser_on (the commanded state)
  bool pattern_on = false;        // shutter.pattern_on (the pattern projector commanded on)
  bool pattern_on_known = false;  // the line has shutter.pattern_on
  double pattern_fraction = 0;    // lit_fraction.pattern
  std::filesystem::path image;                    // run folder / files.image
  std::optional<std::filesystem::path> gt_centers;  // run folder / files.centers
  std::optional<std::filesystem::path> gt_buffers;  // run folder / files.gt (depth, normal, ... EXR)
  std::optional<Pose> world_from_cam;
  std::optional<Pose> world_from_tool;  // when the camera rides on a robot tool
  std::optional<SearchAxis> gt_axis;
  int bit_depth = 0;      // 0: unknown
  int png_bit_depth = 0;  // 0: unknown
  double saturation_dn = 0;  // mean DN of a saturated pixel (full well or ADC), 0: unknown
  double t_start_s = 0, t_end_s = 0;

  std::optional<std::filesystem::path> radiance;  // run folder / files.radiance (radiance EXR)

  // A frame to triangulate: one the laser was commanded on for (shutter.laser_on);
  // without that key, one the laser lit (lit_fraction.laser > 0); without either,
  // every frame. A bright frame that laser light bled into (laser_on false,
  // lit_fraction.laser > 0: synchronisation error) is not a laser frame.
  bool IsLaserFrame() const {
    if (laser_on_known) return laser_on;
    return !shutter_known || laser_fraction > 0;
  }
  // A frame the pattern projector was commanded on for (shutter.pattern_on);
  // without that key, one it lit (lit_fraction.pattern > 0).
  bool IsPatternFrame() const { return pattern_on_known ? pattern_on : pattern_fraction > 0; }
  // A bright frame that can give colour: neither a laser frame nor a pattern
  // frame (structured light is no flood illumination: a colour taken there
  // is the pattern's).
  bool IsColourFrame() const { return !IsLaserFrame() && !IsPatternFrame(); }
  // Largest sample value of the frame's image for a sample type whose own full
  // scale is type_full_scale: 2^bit_depth - 1 for a 16-bit image holding raw DN
  // (LSB-aligned), otherwise the type's full scale.
  double FullScale(double type_full_scale) const;
  // The value a saturated pixel reads in the frame's image: saturation_dn in
  // the image's units (the top 8 bits in an 8-bit image of a deeper sensor),
  // at most FullScale; FullScale when unknown.
  double SaturationLevel(double type_full_scale) const;
};

// The largest value of a sample type as image readers give it: 1 for float
// images, the integer type's maximum otherwise (the type_full_scale of FullScale).
template <typename T>
constexpr double TypeFullScale() {
  if constexpr (std::is_floating_point_v<T>) {
    return 1.0;
  } else {
    return double(std::numeric_limits<T>::max());
  }
}

// Frames sorted by index. Throws lt::InputError for a missing run folder or
// manifest, an invalid line, a duplicate index.
std::vector<RunFrame> ReadRunManifest(const std::filesystem::path& run_dir);

// The scanner geometry of a run.
struct RunRig {
  Camera camera;
  std::vector<Plane> planes_in_cam;  // global plane numbers: sheets of laser 0 first, then laser 1, ...
  int bit_depth = 0;                 // image sensor ADC bits, 0 when unknown
  double black_level_dn = 0;
  ColorFilter color_filter = ColorFilter::kMono;  // the raw images' mosaic
  // Each laser's wavelength in m (global laser order), 0 where the rig does not give it.
  std::vector<double> laser_wavelength_m;
  // The image sensor's quantum efficiency table (image_sensor.quantum_efficiency):
  // wavelengths, and per channel R, G, B (a mono sensor: its one table in all
  // three); empty when the rig does not give it.
  std::vector<double> qe_wavelength_m;
  std::array<std::vector<double>, 3> qe;
  // The image sensor's noise figures (image_sensor.system_gain_dn_per_e: K at
  // the run's gain; dark_noise_e), 0 and -1 when the rig does not give them.
  double system_gain_dn_per_e = 0;
  double dark_noise_e = -1;
  std::filesystem::path source;      // the file read
};

// The threshold and background level of stripe extraction on one frame of a
// run: `threshold` and `background` as given, or, when kAuto (NaN), 10% of the
// frame's full scale (from its bit depth; type_full_scale is the image sample
// type's: 255, 65535 or 1) and the image sensor's black level (in the top 8
// bits for an 8-bit image of a deeper sensor).
struct ExtractionLevels {
  double threshold = 0, background = 0;
};
ExtractionLevels FrameExtractionLevels(double threshold, double background, const RunFrame& frame, int rig_bit_depth,
                                       double rig_black_level_dn, double type_full_scale);
// A frame's image must have the camera's size (its pixels are the camera's):
// throws lt::InputError naming the image, "the image is WxH but the camera
// (camera_source) is WxH (frame N, <where in the manifest>)", otherwise.
void CheckFrameImageSize(const AnyImage& image, const RunFrame& frame, const Camera& camera,
                         const std::string& camera_source);
// The largest sample value of an image's type: 255, 65535, or 1 for float.
double ImageTypeFullScale(const AnyImage& image);

// Reads rig.json (render/rig JSON: "camera" in scene-file form, "lasers" with
// "sheet_planes_in_cam" and optional "wavelength_nm", "image_sensor" with an
// optional "quantum_efficiency" in the scene file's form); without it, the
// "sensor" section of scene.json. Throws lt::InputError naming the file and
// JSON pointer.
RunRig ReadRunRig(const std::filesystem::path& run_dir);
// Whether the run folder holds rig.json or scene.json (what ReadRunRig reads).
bool HasRunRig(const std::filesystem::path& run_dir);

// What a folder without rig.json is taken for, as scan and calibrate both warn
// it: "DIR holds no rig.json: the camera is FILE's, the image sensor's black
// level 0 (--background sets it), mono (--bayer sets a mosaic), its bit depth
// HOW", each part left out where nothing is assumed; "" when nothing is.
struct NoRigAssumptions {
  std::string camera_source;  // the file the camera is taken from; "" none
  bool black_level_zero = false;
  bool mono = false;
  std::string bit_depth;  // where the bit depth comes from; "" not said
};
std::string NoRigWarning(const std::string& run_dir, const NoRigAssumptions& a);

}  // namespace lt
