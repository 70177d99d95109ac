#include "render/frame_writer.h"

#include <filesystem>

#include "core/atomic_file.h"
#include "core/image_io.h"

namespace lt {

Image<uint8_t> RawTo8Bit(const Image<uint16_t>& raw, int bit_depth) {
  Image<uint8_t> out(raw.width, raw.height, raw.channels);
  int shift = std::max(0, bit_depth - 8);
  for (size_t i = 0; i < raw.pixels.size(); ++i) out.pixels[i] = uint8_t(std::min(255, raw.pixels[i] >> shift));
  return out;
}

nlohmann::json WriteFrame(const RunFolder& run, const RenderedFrame& frame, int index, const SceneFile& scene,
                          uint64_t seed, int spp) {
  const auto& dir = run.dir();
  const OutputSettings& output = scene.output;
  const int bits = scene.sensor.image_sensor.bit_depth();
  nlohmann::json files;
  files["image"] = RunFolder::FrameImageName(index);
  if (output.png_bit_depth == 16) {
    WriteImage(dir / RunFolder::FrameImageName(index), frame.raw);
  } else {
    WriteImage(dir / RunFolder::FrameImageName(index), RawTo8Bit(frame.raw, bits));
  }
  // radiance/ and gt/ exist only in runs that write them.
  if (output.write_radiance) {
    std::filesystem::create_directories(dir / "radiance");
    files["radiance"] = RunFolder::RadianceName(index);
    WriteImage(dir / RunFolder::RadianceName(index), frame.radiance, true, {"R", "G", "B", "laser"});
  }
  if (output.write_ground_truth) {
    std::filesystem::create_directories(dir / "gt");
    const auto& gt = frame.gt;
    const int w = gt.depth.width, h = gt.depth.height;
    Image<float> buffers(w, h, 7);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        float* p = &buffers.At(x, y, 0);
        p[0] = gt.depth.At(x, y);
        for (int c = 0; c < 3; ++c) p[1 + c] = gt.normal.At(x, y, c);
        p[4] = gt.instance.At(x, y);
        p[5] = gt.material.At(x, y);
        p[6] = gt.plane.At(x, y);
      }
    }
    files["gt"] = RunFolder::GroundTruthName(index);
    WriteImage(dir / RunFolder::GroundTruthName(index), buffers, true,
               {"Z", "N.X", "N.Y", "N.Z", "instance", "material", "plane"});
    if (frame.shutter.laser_fraction > 0 && !scene.sensor.lasers.empty()) {
      files["centers"] = RunFolder::CentersName(index);
      WriteFileAtomically(dir / RunFolder::CentersName(index), StripeCentersCsv(frame.centers));
    }
  }
  const ShutterFrame& sf = frame.shutter;
  nlohmann::json line = {
      {"index", index},
      {"label", sf.label},
      {"t_start_s", sf.t_start_s},
      {"t_end_s", sf.t_end_s},
      {"exposure_s", sf.exposure_s},
      {"shutter", {{"laser_on", sf.laser_on}, {"pattern_on", sf.pattern_on}, {"led_on", sf.led_on}}},
      {"lit_fraction",
       {{"laser", sf.laser_fraction}, {"pattern", sf.pattern_fraction}, {"led", sf.led_fraction}}},
      {"world_from_cam", PoseToJson(frame.world_from_cam)},
      {"world_from_cam_start", PoseToJson(WorldFromCamAt(scene.motion, sf.t_start_s))},
      {"world_from_cam_end", PoseToJson(WorldFromCamAt(scene.motion, sf.t_end_s))},
      {"files", files},
      {"seed", seed},
      {"spp", spp},
      {"gt_axis", ScanAxisName(frame.axis)},
      {"stripe_centers", frame.centers.size()},
      {"bit_depth", bits},
      {"saturation_dn", scene.sensor.image_sensor.SaturationDn(sf.analog_gain_db)},
      {"png_bit_depth", output.png_bit_depth},
      {"stats",
       {{"rays", frame.stats.rays},
        {"samples", frame.stats.samples},
        {"near_pixels", frame.stats.near_pixels},
        {"edge_pixels", frame.stats.edge_pixels},
        {"light_paths", frame.stats.light_paths},
        {"entry_tree_slices", frame.stats.entry_tree_slices},
        {"render_ms", frame.stats.render_ms},
        {"ground_truth_ms", frame.stats.ground_truth_ms}}}};
  frame.stats.pass_ms.ForEach([&](const char* name, double ms) { line["stats"]["pass_ms"][name] = ms; });
  // The robot tool (flange) pose when the camera rides on one (hand-eye calibration).
  if (auto tool = WorldFromToolAt(scene.motion, 0.5 * (sf.t_start_s + sf.t_end_s))) {
    line["world_from_tool"] = PoseToJson(*tool);
  }
  if (scene.print) {
    line["stats"]["print_chunks_rebuilt"] = frame.stats.print_chunks_rebuilt;
    line["stats"]["print_triangles_rebuilt"] = frame.stats.print_triangles_rebuilt;
    line["stats"]["print_triangles"] = frame.stats.print_triangles;
  }
  return line;
}

}  // namespace lt
