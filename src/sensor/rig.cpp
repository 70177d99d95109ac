// The parsing of the scene file's `sensor` section (sensor/rig.h): camera, image sensor,
// lasers, pattern projector, LED, shutter and the whole rig. SensorRigToJson (writing the
// rig as JSON) is in rig_json.cpp.
#include "sensor/rig.h"

#include <cmath>

#include "core/error.h"
#include "core/image_io.h"
#include "core/pose.h"
#include "sensor/param_error.h"

namespace lt {

using json::Object;
using json::Range;
using json::Value;

namespace {

constexpr double kDeg = M_PI / 180.0;

// Splits "file: /pointer" (Value::where) into the pointer and appends key.
std::string JoinPointer(const Object& o, const std::string& key) {
  std::string where = o.value().where();
  if (key.empty()) return where;
  if (!where.empty() && where.back() == '/') return where + key;
  return where + "/" + key;
}

std::vector<double> NumberList(const Value& v, size_t min_size, Range range) {
  std::vector<double> out;
  for (const Value& e : v.Array(min_size)) out.push_back(e.Number(range));
  return out;
}

// OpenCV's distCoeffs (BrownConradyFromOpenCv names the lengths and terms it takes).
BrownConradyCoeffs ReadOpenCvDistortion(const Value& v) {
  const std::vector<Value> items = v.Array();
  std::vector<double> d;
  for (const Value& e : items) d.push_back(e.Number());
  BrownConradyCoeffs c;
  const OpenCvDistCoeffsProblem p = BrownConradyFromOpenCv(d, &c);
  if (!p.ok()) (p.element < 0 ? v : items[p.element]).Fail(p.problem);
  return c;
}

DistortionModel ReadDistortion(const Object& o, CameraParams* p) {
  std::string model = o.Enum("model", {"none", "brown_conrady", "fisheye"});
  if (model == "none") {
    o.Finish();
    return DistortionModel::kNone;
  }
  const bool bc = model == "brown_conrady";
  const std::vector<std::string> names = bc ? std::vector<std::string>{"k1", "k2", "p1", "p2", "k3"}
                                            : std::vector<std::string>{"k1", "k2", "k3", "k4"};
  std::vector<double> c(names.size(), 0.0);
  if (auto coeffs = o.Find("coefficients")) {
    for (const auto& n : names) {
      if (o.Has(n)) o.Get(n).Fail("give either \"coefficients\" or named coefficients, not both");
    }
    if (bc) {
      const BrownConradyCoeffs b = ReadOpenCvDistortion(*coeffs);
      c = {b.k1, b.k2, b.p1, b.p2, b.k3};
    } else {
      c = coeffs->Numbers(names.size());
    }
  } else {
    for (size_t i = 0; i < names.size(); ++i) c[i] = o.Number(names[i], 0.0);
  }
  o.Finish();
  if (bc) {
    p->brown_conrady = {c[0], c[1], c[2], c[3], c[4]};
    return DistortionModel::kBrownConrady;
  }
  p->fisheye = {c[0], c[1], c[2], c[3]};
  return DistortionModel::kFisheye;
}

std::optional<GaussianBeam> ReadGaussianBeam(const Object& o, double wavelength_m) {
  GaussianBeam g;
  g.waist_m = o.Number("waist_um", Range::Positive()) * 1e-6;
  g.rayleigh_range_m = o.Number("rayleigh_range_mm", M_PI * g.waist_m * g.waist_m / wavelength_m * 1e3,
                                Range::Positive()) * 1e-3;
  g.waist_distance_m = o.Number("waist_distance_mm", 0.0) * 1e-3;
  o.Finish();
  return g;
}

}  // namespace

[[noreturn]] void ThrowAt(const json::Object& object, const ParamError& e) {
  throw InputError(JoinPointer(object, e.key()), e.message());
}

// ---------------------------------------------------------------- camera

Camera ParseCamera(const Object& o) {
  CameraParams p;
  Value res = o.Get("resolution");
  auto wh = res.Array(2, 2);
  p.width = int(wh[0].Integer(Range::Closed(1, 1 << 16)));
  p.height = int(wh[1].Integer(Range::Closed(1, 1 << 16)));
  p.pixel_pitch_m = o.Number("pixel_pitch_um", Range::Positive()) * 1e-6;
  const bool pixel_form = o.Has("fx") || o.Has("fy") || o.Has("cx") || o.Has("cy");
  if (pixel_form) {
    if (o.Has("focal_length_mm") || o.Has("principal_point_px")) {
      o.Fail("give the intrinsics either in pixels (fx, fy, cx, cy) or as focal_length_mm (+ principal_point_px), "
             "not both");
    }
    p.fx = o.Number("fx", Range::Positive());
    p.fy = o.Number("fy", Range::Positive());
    p.cx = o.Number("cx");
    p.cy = o.Number("cy");
  } else {
    if (!o.Has("focal_length_mm")) {
      o.Fail("missing intrinsics: give fx, fy, cx, cy (pixels) or focal_length_mm");
    }
    double f = o.Number("focal_length_mm", Range::Positive()) * 1e-3;
    p.fx = p.fy = f / p.pixel_pitch_m;
    p.cx = 0.5 * (p.width - 1);
    p.cy = 0.5 * (p.height - 1);
    if (auto pp = o.Find("principal_point_px")) {
      auto c = pp->Numbers(2);
      p.cx = c[0];
      p.cy = c[1];
    }
  }
  if (auto d = o.FindObject("distortion")) p.distortion = ReadDistortion(*d, &p);
  p.f_number = o.Number("f_number", Range::Positive());
  if (o.Has("focus_distance_m")) p.focus_distance_m = o.Number("focus_distance_m", Range::Positive());
  o.Finish();
  return WithPointer(o, [&] { return Camera(p); });
}

// ---------------------------------------------------------------- image sensor

ImageSensor ParseImageSensor(const Object& o) {
  ImageSensorParams p;
  p.color_filter = *ParseColorFilter(o.Enum("color_filter", "mono", {"mono", "rggb", "bggr", "grbg", "gbrg"}));
  const bool mono = p.color_filter == ColorFilter::kMono;
  if (auto q = o.Find("quantum_efficiency")) {
    if (q->IsNumber()) {
      if (!mono) q->Fail("a Bayer sensor needs per-channel tables: {\"wavelength_nm\": [...], \"r\": [...], \"g\": [...], \"b\": [...]}");
      double v = q->Number(Range::Closed(0, 1));
      p.qe_wavelength_m = {550e-9};
      p.qe = {{{v}, {v}, {v}}};
    } else {
      Object t = q->AsObject();
      Value wl = t.Get("wavelength_nm");
      p.qe_wavelength_m = NumberList(wl, 1, Range::Positive());
      for (double& w : p.qe_wavelength_m) w *= 1e-9;
      auto read = [&](const char* key) {
        Value v = t.Get(key);
        auto list = NumberList(v, 1, Range::Closed(0, 1));
        if (list.size() != p.qe_wavelength_m.size()) {
          v.Fail("must have one value per wavelength (" + std::to_string(p.qe_wavelength_m.size()) + "), got " +
                 std::to_string(list.size()));
        }
        return list;
      };
      if (mono) {
        auto m = read("mono");
        p.qe = {m, m, m};
      } else {
        p.qe = {read("r"), read("g"), read("b")};
      }
      t.Finish();
    }
  } else if (!mono) {
    o.Fail("a Bayer sensor needs \"quantum_efficiency\" with per-channel tables (r, g, b)");
  }
  if (auto b = o.Find("band_wavelengths_nm")) {
    auto v = b->Numbers(3, Range::Positive());
    p.band_wavelength_m = {v[0] * 1e-9, v[1] * 1e-9, v[2] * 1e-9};
  }
  p.full_well_e = o.Number("full_well_e", p.full_well_e, Range::Positive());
  p.system_gain_dn_per_e = o.Number("system_gain_dn_per_e", p.system_gain_dn_per_e, Range::Positive());
  p.analog_gain_db = o.Number("analog_gain_db", 0.0, Range::Closed(-40, 60));
  p.dark_noise_e = o.Number("dark_noise_e", p.dark_noise_e, Range::NonNegative());
  p.dark_current_e_per_s = o.Number("dark_current_e_per_s", 0.0, Range::NonNegative());
  p.black_level_dn = o.Number("black_level_dn", 0.0, Range::NonNegative());
  p.bit_depth = int(o.Integer("bit_depth", 12, Range::Closed(1, 16)));
  p.prnu = o.Number("prnu_percent", 0.0, Range::ClosedOpen(0, 100)) / 100.0;
  p.dsnu_e = o.Number("dsnu_e", 0.0, Range::NonNegative());
  p.fixed_pattern_seed = uint64_t(o.Integer("fixed_pattern_seed", 1, Range::NonNegative()));
  o.Finish();
  return WithPointer(o, [&] { return ImageSensor(p); });
}

// ---------------------------------------------------------------- laser

LaserProjector ParseLaser(const Object& o) {
  LaserParams p;
  p.power_w = o.Number("power_mw", Range::Positive()) * 1e-3;
  p.wavelength_m = o.Number("wavelength_nm", Range::Closed(200, 2000)) * 1e-9;
  p.cam_from_projector = ReadPose(o.Get("cam_from_projector"));
  p.fan_profile = o.Enum("fan_profile", "flat_top", {"flat_top", "gaussian"}) == "flat_top" ? FanProfile::kFlatTop
                                                                                            : FanProfile::kGaussian;
  p.fan_angle_rad = o.Number("fan_angle_deg", 60.0, Range::OpenClosed(0, 360)) * kDeg;
  if (auto g = o.FindObject("gaussian_beam")) {
    if (o.Has("divergence_deg")) o.Get("divergence_deg").Fail("give divergence_deg or gaussian_beam, not both");
    p.gaussian_beam = ReadGaussianBeam(*g, p.wavelength_m);
  } else {
    p.divergence_rad = o.Number("divergence_deg", 0.1, Range::OpenClosed(0, 40)) * kDeg;
  }
  if (auto angles = o.Find("sheet_angles_deg")) {
    if (o.Has("sheet_count") || o.Has("sheet_spacing_deg")) {
      angles->Fail("give sheet_angles_deg or sheet_count with sheet_spacing_deg, not both");
    }
    p.sheet_angles_rad = NumberList(*angles, 1, Range::Open(-90, 90));
    for (double& a : p.sheet_angles_rad) a *= kDeg;
  } else {
    const int64_t count = o.Integer("sheet_count", 1, Range::AtLeast(1));
    if (count > kMaxRigSheets) o.Get("sheet_count").Fail("must be <= " + std::to_string(kMaxRigSheets) + ", got " + std::to_string(count));
    const int n = int(count);
    double spacing = 0.0;
    if (n > 1) {
      spacing = o.Number("sheet_spacing_deg", Range::Positive()) * kDeg;
      if (!((n - 1) * spacing < M_PI)) {
        o.Get("sheet_spacing_deg").Fail("(sheet_count - 1) x sheet_spacing_deg must be below 180 deg");
      }
    } else {
      o.Accept({"sheet_spacing_deg"});
    }
    p.sheet_angles_rad = EvenSheetAngles(n, spacing);
  }
  if (auto sp = o.Find("sheet_power")) {
    p.sheet_power = NumberList(*sp, 1, Range::NonNegative());
  }
  o.Finish();
  return WithPointer(o, [&] { return LaserProjector(p); });
}

// ---------------------------------------------------------------- pattern, LED

PatternProjector ParsePatternProjector(const Object& o) {
  PatternProjectorParams p;
  const Value image = o.Get("image");
  const std::filesystem::path image_path = image.ExistingFile("pattern image");
  try {
    p.pattern = ReadImageFloat(image_path);
  } catch (const InputError& e) {
    image.Fail(e.what());
  }
  Value fov = o.Get("fov_deg");
  if (fov.IsNumber()) {
    p.horizontal_fov_rad = fov.Number(Range::Open(0, 180)) * kDeg;
  } else {
    auto v = fov.Numbers(2, Range::Open(0, 180));
    p.horizontal_fov_rad = v[0] * kDeg;
    p.vertical_fov_rad = v[1] * kDeg;
  }
  p.power_w = o.Number("power_mw", Range::Positive()) * 1e-3;
  p.wavelength_m = o.Number("wavelength_nm", Range::Closed(200, 2000)) * 1e-9;
  p.cam_from_projector = ReadPose(o.Get("cam_from_projector"));
  o.Finish();
  return WithPointer(o, [&] { return PatternProjector(p); });
}

Led ParseLed(const Object& o) {
  LedParams p;
  auto size = o.Get("size_m").Numbers(2, Range::Positive());
  p.width_m = size[0];
  p.height_m = size[1];
  Value r = o.Get("radiance_w_per_m2_sr");
  if (r.IsNumber()) {
    double total = r.Number(Range::NonNegative());
    p.radiance = {total / 3, total / 3, total / 3};
  } else {
    auto v = r.Numbers(3, Range::NonNegative());
    p.radiance = {v[0], v[1], v[2]};
  }
  p.cam_from_led = ReadPose(o.Get("cam_from_led"));
  o.Finish();
  return WithPointer(o, [&] { return Led(p); });
}

// ---------------------------------------------------------------- shutter

ShutterSchedule ParseShutter(const Object& o) {
  ShutterParams p;
  p.frame_period_s = o.Number("frame_period_ms", Range::Positive()) * 1e-3;
  p.exposure_change_overhead_s = o.Number("exposure_change_overhead_ms", 0.0, Range::NonNegative()) * 1e-3;
  p.sync_offset_s = o.Number("sync_offset_us", 0.0) * 1e-6;
  p.sync_jitter_s = o.Number("sync_jitter_us", 0.0, Range::NonNegative()) * 1e-6;
  p.start_time_s = o.Number("start_time_s", 0.0);
  const bool has_cycle = o.Has("cycle"), has_alt = o.Has("alternating");
  if (has_cycle == has_alt) o.Fail("give exactly one of \"cycle\" and \"alternating\"");
  if (has_alt) {
    Object a = o.GetObject("alternating");
    double bright = a.Number("bright_exposure_us", Range::Positive()) * 1e-6;
    double dim = a.Number("dim_exposure_us", Range::Positive()) * 1e-6;
    bool led = a.Bool("led_in_bright", true);
    std::string first = a.Enum("first", "bright", {"bright", "dim"});
    a.Finish();
    ShutterParams alt = AlternatingShutter(bright, dim, p.frame_period_s, led);
    p.cycle = alt.cycle;
    if (first == "dim") std::swap(p.cycle[0], p.cycle[1]);
  } else {
    p.cycle.clear();
    auto entries = o.Get("cycle").Array(1);
    for (size_t i = 0; i < entries.size(); ++i) {
      Object e = entries[i].AsObject();
      ShutterFrameSpec f;
      f.label = e.String("label", "frame" + std::to_string(i));
      f.exposure_s = e.Number("exposure_us", Range::Positive()) * 1e-6;
      f.laser = e.Bool("laser", false);
      f.pattern = e.Bool("pattern", false);
      f.led = e.Bool("led", false);
      if (e.Has("analog_gain_db")) f.analog_gain_db = e.Number("analog_gain_db", Range::Closed(-40, 60));
      e.Finish();
      p.cycle.push_back(f);
    }
  }
  o.Finish();
  return WithPointer(o, [&] { return ShutterSchedule(p); });
}

// ---------------------------------------------------------------- rig

SensorRig ParseSensorRig(const Object& s) {
  SensorRig rig;
  rig.camera = ParseCamera(s.GetObject("camera"));
  if (auto o = s.FindObject("image_sensor")) rig.image_sensor = ParseImageSensor(*o);
  int sheets = 0;
  if (auto l = s.Find("lasers")) {
    for (const Value& v : l->Array()) {
      rig.lasers.push_back(ParseLaser(v.AsObject()));
      sheets += rig.lasers.back().sheet_count();
      if (int(rig.lasers.size()) > kMaxRigEmitters) {
        v.Fail("a rig holds at most " + std::to_string(kMaxRigEmitters) + " lasers and pattern projectors together");
      }
      if (sheets > kMaxRigSheets) {
        v.Fail("the lasers up to this one have " + std::to_string(sheets) + " sheets; a rig holds at most " +
               std::to_string(kMaxRigSheets) + " (lasers' sheets and the pattern projector together)");
      }
    }
  }
  if (auto o = s.FindObject("pattern_projector")) {
    if (int(rig.lasers.size()) + 1 > kMaxRigEmitters || sheets + 1 > kMaxRigSheets) {
      o->Fail("the rig is full: a rig holds at most " + std::to_string(kMaxRigEmitters) +
              " lasers and pattern projectors and " + std::to_string(kMaxRigSheets) + " sheets, the pattern projector's one included");
    }
    rig.pattern = ParsePatternProjector(*o);
  }
  if (auto o = s.FindObject("led")) rig.led = ParseLed(*o);
  if (auto o = s.FindObject("shutter")) rig.shutter = ParseShutter(*o);
  s.Finish();
  return rig;
}

}  // namespace lt
