#include "pipeline/run_folder_reader.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <type_traits>
#include <variant>

#include "core/error.h"
#include "core/json_reader.h"
#include "sensor/rig.h"

namespace lt {

namespace fs = std::filesystem;
using json::Object;
using json::Range;
using json::Value;

namespace {

void RequireRunFolder(const fs::path& run_dir) {
  if (!fs::exists(run_dir)) throw InputError(run_dir.string(), "run folder not found");
  if (!fs::is_directory(run_dir)) throw InputError(run_dir.string(), "is not a folder (expected a run folder)");
}

RunFrame ParseLine(const fs::path& run_dir, const std::string& text, const std::string& where) {
  // A syntax error names the line and column; errors inside the object name the line and JSON pointer.
  try {
    nlohmann::json checked = nlohmann::json::parse(text);
    (void)checked;
  } catch (const nlohmann::json::parse_error& e) {
    // "[json.exception.parse_error.101] parse error at line 1, column 23: syntax error ...": keep the reason.
    std::string msg = e.what();
    auto pos = msg.find(", column ");
    pos = pos == std::string::npos ? msg.find("] ") : msg.find(": ", pos);
    if (pos != std::string::npos) msg = msg.substr(pos + 2);
    throw InputError(where + ":" + std::to_string(e.byte > 0 ? e.byte : 1), "invalid JSON: " + msg);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where, std::string("invalid JSON: ") + e.what());
  }
  json::Document doc = json::Document::Parse(text, where, run_dir);
  Object o = doc.Root().AsObject();
  RunFrame f;
  f.where = where;
  f.index = int(o.Integer("index", Range::Closed(0, 1e9)));
  f.label = o.String("label", "");
  Object files = o.GetObject("files");
  const std::string image = files.String("image");
  if (image.empty()) files.Get("image").Fail("must name the frame's image file");
  f.image = run_dir / image;
  if (files.Has("centers")) f.gt_centers = run_dir / files.String("centers");
  if (files.Has("gt")) f.gt_buffers = run_dir / files.String("gt");
  if (files.Has("radiance")) f.radiance = run_dir / files.String("radiance");
  if (auto s = o.FindObject("shutter")) {
    if (s->Has("laser_on")) {
      f.laser_on = s->Bool("laser_on", false);
      f.shutter_known = true;
      f.laser_on_known = true;
    }
    if (s->Has("pattern_on")) {
      f.pattern_on = s->Bool("pattern_on", false);
      f.pattern_on_known = true;
    }
  }
  if (auto l = o.FindObject("lit_fraction")) {
    if (l->Has("laser")) {
      f.laser_fraction = l->Number("laser", Range::Closed(0, 1));
      f.shutter_known = true;
    }
    if (l->Has("pattern")) f.pattern_fraction = l->Number("pattern", Range::Closed(0, 1));
  }
  if (auto p = o.Find("world_from_cam")) f.world_from_cam = ReadPose(*p);
  if (auto p = o.Find("world_from_tool")) f.world_from_tool = ReadPose(*p);
  if (o.Has("gt_axis")) f.gt_axis = o.Enum("gt_axis", {"rows", "cols"}) == "rows" ? SearchAxis::kRows : SearchAxis::kCols;
  f.bit_depth = int(o.Integer("bit_depth", 0, Range::Closed(1, 16)));
  f.saturation_dn = o.Number("saturation_dn", 0.0, Range::NonNegative());
  if (o.Has("png_bit_depth")) {
    f.png_bit_depth = int(o.Integer("png_bit_depth", Range::Closed(8, 16)));
    if (f.png_bit_depth != 8 && f.png_bit_depth != 16) o.Get("png_bit_depth").Fail("must be 8 or 16");
  }
  f.t_start_s = o.Number("t_start_s", 0.0);
  f.t_end_s = o.Number("t_end_s", f.t_start_s);
  // Other keys (render statistics, seeds, ...) are the writer's business: not checked.
  return f;
}

}  // namespace

double RunFrame::FullScale(double type_full_scale) const {
  if (type_full_scale == 65535.0 && bit_depth > 0 && png_bit_depth != 8) return std::ldexp(1.0, bit_depth) - 1.0;
  return type_full_scale;
}

double RunFrame::SaturationLevel(double type_full_scale) const {
  const double full = FullScale(type_full_scale);
  if (!(saturation_dn > 0) || bit_depth <= 0) return full;
  // An 8-bit image of a deeper sensor holds the top 8 bits of each DN.
  const double dn = type_full_scale == 255.0 && bit_depth > 8 ? std::floor(std::ldexp(saturation_dn, 8 - bit_depth))
                                                               : saturation_dn;
  return std::min(full, dn);
}

std::vector<RunFrame> ReadRunManifest(const fs::path& run_dir) {
  RequireRunFolder(run_dir);
  const fs::path path = run_dir / "manifest.jsonl";
  if (!fs::exists(path)) throw InputError(path.string(), "run manifest not found");
  std::ifstream in(path);
  if (!in) throw InputError(path.string(), "cannot open run manifest");
  std::map<int, RunFrame> frames;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = path.string() + ":" + std::to_string(line_no);
    RunFrame f = ParseLine(run_dir, line, where);
    auto [it, inserted] = frames.emplace(f.index, f);
    if (!inserted) {
      throw InputError(where, "frame " + std::to_string(f.index) + " appears twice (first at " + it->second.where + ")");
    }
  }
  if (in.bad()) throw InputError(path.string(), "cannot read run manifest");
  std::vector<RunFrame> out;
  for (auto& [index, f] : frames) out.push_back(std::move(f));
  return out;
}

namespace {

// A non-empty array of numbers within `range`.
std::vector<double> NumberList(const Value& v, Range range) {
  std::vector<double> out;
  for (const Value& e : v.Array(1)) out.push_back(e.Number(range));
  return out;
}

// image_sensor.quantum_efficiency as the scene file gives it: one number (a mono
// sensor), or {"wavelength_nm": [...], "mono": [...]} / {"wavelength_nm": [...],
// "r": [...], "g": [...], "b": [...]}.
void ReadQuantumEfficiency(const Value& q, ColorFilter filter, RunRig* rig) {
  const bool mono = filter == ColorFilter::kMono;
  if (q.IsNumber()) {
    if (!mono) q.Fail("a Bayer sensor needs per-channel tables: {\"wavelength_nm\": [...], \"r\": [...], \"g\": [...], \"b\": [...]}");
    const double v = q.Number(Range::Closed(0, 1));
    rig->qe_wavelength_m = {550e-9};
    rig->qe = {{{v}, {v}, {v}}};
    return;
  }
  Object t = q.AsObject();
  Value wl = t.Get("wavelength_nm");
  const std::vector<double> wavelengths = NumberList(wl, Range::Positive());
  for (size_t i = 1; i < wavelengths.size(); ++i) {
    if (!(wavelengths[i] > wavelengths[i - 1])) wl.Fail("wavelengths must be increasing");
  }
  auto read = [&](const char* key) {
    Value v = t.Get(key);
    std::vector<double> list = NumberList(v, Range::Closed(0, 1));
    if (list.size() != wavelengths.size()) {
      v.Fail("must have one value per wavelength (" + std::to_string(wavelengths.size()) + "), got " +
             std::to_string(list.size()));
    }
    return list;
  };
  if (mono) {
    const std::vector<double> m = read("mono");
    rig->qe = {m, m, m};
  } else {
    rig->qe = {read("r"), read("g"), read("b")};
  }
  t.Finish();
  rig->qe_wavelength_m = wavelengths;
  for (double& w : rig->qe_wavelength_m) w *= 1e-9;
}

RunRig ReadRigJson(const fs::path& path) {
  json::Document doc = json::Document::Load(path);
  Object root = doc.Root().AsObject();
  RunRig rig;
  rig.source = path;
  rig.camera = ParseCamera(root.GetObject("camera"));
  if (auto lasers = root.Find("lasers")) {
    for (const Value& lv : lasers->Array()) {
      Object l = lv.AsObject();
      l.Accept({"power_mw", "cam_from_projector"});
      rig.laser_wavelength_m.push_back(l.Has("wavelength_nm") ? l.Number("wavelength_nm", Range::Closed(200, 2000)) * 1e-9
                                                               : 0.0);
      for (const Value& pv : l.Get("sheet_planes_in_cam").Array(1)) {
        Object p = pv.AsObject();
        Eigen::Vector3d n = p.Vec3("n");
        const double norm = n.norm();
        if (!(std::abs(norm - 1.0) < 1e-6)) p.Get("n").Fail("must be a unit vector, got norm " + FormatNumber(norm));
        const double scale = std::abs(norm - 1.0) > 1e-12 ? norm : 1.0;  // keep unit normals bit-exact
        rig.planes_in_cam.push_back({n / scale, p.Number("d") / scale});
        p.Accept({"power_mw"});
        p.Finish();
      }
      l.Finish();
    }
  }
  if (auto s = root.FindObject("image_sensor")) {
    rig.bit_depth = int(s->Integer("bit_depth", 0, Range::Closed(1, 16)));
    rig.black_level_dn = s->Number("black_level_dn", 0.0, Range::NonNegative());
    rig.color_filter = *ParseColorFilter(s->Enum("color_filter", "mono", {"mono", "rggb", "bggr", "grbg", "gbrg"}));
    if (auto q = s->Find("quantum_efficiency")) ReadQuantumEfficiency(*q, rig.color_filter, &rig);
    rig.system_gain_dn_per_e = s->Number("system_gain_dn_per_e", 0.0, Range::Positive());
    rig.dark_noise_e = s->Number("dark_noise_e", -1.0, Range::NonNegative());
    s->Accept({"full_well_e"});
    s->Finish();
  }
  root.Finish();
  return rig;
}

RunRig ReadSceneSensor(const fs::path& path) {
  json::Document doc = json::Document::Load(path);
  Object root = doc.Root().AsObject();
  SensorRig sensor = ParseSensorRig(root.GetObject("sensor"));
  // The rest of the scene (objects, materials, ...) is the renderer's: not read here.
  RunRig rig;
  rig.source = path;
  rig.camera = sensor.camera;
  for (const LaserProjector& l : sensor.lasers) {
    for (int k = 0; k < l.sheet_count(); ++k) rig.planes_in_cam.push_back(l.SheetPlane(k));
    rig.laser_wavelength_m.push_back(l.wavelength_m());
  }
  rig.qe_wavelength_m = sensor.image_sensor.params().qe_wavelength_m;
  rig.qe = sensor.image_sensor.params().qe;
  rig.system_gain_dn_per_e = sensor.image_sensor.SystemGain();
  rig.dark_noise_e = sensor.image_sensor.params().dark_noise_e;
  rig.bit_depth = sensor.image_sensor.bit_depth();
  rig.black_level_dn = sensor.image_sensor.params().black_level_dn;
  rig.color_filter = sensor.image_sensor.color_filter();
  return rig;
}

}  // namespace

RunRig ReadRunRig(const fs::path& run_dir) {
  RequireRunFolder(run_dir);
  if (fs::exists(run_dir / "rig.json")) return ReadRigJson(run_dir / "rig.json");
  if (fs::exists(run_dir / "scene.json")) return ReadSceneSensor(run_dir / "scene.json");
  throw InputError(run_dir.string(), "holds neither rig.json nor scene.json: the camera and laser planes are unknown "
                                     "(a calibration file with both, from lasertwin calibrate, gives them: scan --calib)");
}

bool HasRunRig(const fs::path& run_dir) {
  return fs::exists(run_dir / "rig.json") || fs::exists(run_dir / "scene.json");
}

std::string NoRigWarning(const std::string& run_dir, const NoRigAssumptions& a) {
  std::string sensor;
  if (a.black_level_zero) sensor = "the image sensor's black level 0 (--background sets it)";
  if (a.mono) sensor += sensor.empty() ? "the image sensor is mono (--bayer sets a mosaic)" : ", mono (--bayer sets a mosaic)";
  if (!a.bit_depth.empty()) sensor += (sensor.empty() ? "the image sensor's bit depth " : ", its bit depth ") + a.bit_depth;
  if (sensor.empty() && a.camera_source.empty()) return "";
  const std::string camera = a.camera_source.empty() ? "" : "the camera is " + a.camera_source + "'s";
  return run_dir + " holds no rig.json: " + camera + (camera.empty() || sensor.empty() ? "" : ", ") + sensor;
}

ExtractionLevels FrameExtractionLevels(double threshold, double background, const RunFrame& frame, int rig_bit_depth,
                                       double rig_black_level_dn, double type_full_scale) {
  ExtractionLevels l;
  // A manifest line without bit_depth (a capture tool's) has the image sensor's.
  RunFrame f = frame;
  if (f.bit_depth <= 0) f.bit_depth = rig_bit_depth;
  l.threshold = std::isnan(threshold) ? 0.1 * f.FullScale(type_full_scale) : threshold;
  l.background = background;
  if (std::isnan(background)) {
    // The black level in DN; an 8-bit image holds the top 8 bits.
    l.background = rig_black_level_dn;
    if (type_full_scale == 255.0 && rig_bit_depth > 8) l.background = std::ldexp(l.background, 8 - rig_bit_depth);
  }
  return l;
}

void CheckFrameImageSize(const AnyImage& image, const RunFrame& frame, const Camera& camera,
                         const std::string& camera_source) {
  int w = 0, h = 0;
  std::visit(
      [&](const auto& im) {
        w = im.width;
        h = im.height;
      },
      image);
  if (w == camera.width() && h == camera.height()) return;
  auto size = [](int a, int b) { return std::to_string(a) + "x" + std::to_string(b); };
  throw InputError(frame.image.string(), "the image is " + size(w, h) + " but the camera (" + camera_source + ") is " +
                                             size(camera.width(), camera.height()) + " (frame " +
                                             std::to_string(frame.index) + ", " + frame.where + ")");
}

double ImageTypeFullScale(const AnyImage& image) {
  return std::visit([](const auto& im) { return TypeFullScale<std::decay_t<decltype(im.pixels[0])>>(); }, image);
}

}  // namespace lt
