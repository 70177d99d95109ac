// The G-code reader's comments: slicers' layer, type, layer height and filament
// tags, and the layers of a file without layer comments, numbered from the heights
// it extrudes at.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>

#include "core/error.h"
#include "scene/gcode_reader.h"
#include "core/text_fields.h"

namespace lt {
namespace gcode_detail {

namespace {

// The filament diameter of the Ultimaker 2 family, which Cura's UltiGCode flavour is for.
constexpr double kUltimakerFilamentMm = 2.85;
// Marlin's DEFAULT_NOMINAL_FILAMENT_DIA, the diameter its volumetric mode assumes
// until M200 D sets one: for Cura's Marlin(Volumetric) flavour, which states none.
constexpr double kMarlinNominalFilamentMm = 1.75;

// IceSL's layer comment "<layer N>" (N 0 to 999999999, numbered from 0), else none:
// another comment that starts so ("<layer 5 is thin>") is an ordinary comment.
std::optional<int> IceSlLayer(std::string_view c) {
  if (!StartsWith(c, "<layer ") || c.size() < 9 || c.back() != '>' || c.size() > 17) return std::nullopt;
  int n = 0;
  for (char d : c.substr(7, c.size() - 8)) {
    if (d < '0' || d > '9') return std::nullopt;
    n = 10 * n + (d - '0');
  }
  return n;
}

}  // namespace

void GcodeReader::LayersFromZ() {
  // A layer begins at the first move that extrudes at a height above every height at
  // which the current layer has extruded (the end of a rising move counts: a spiral
  // stays one layer); it takes the moves since the previous layer's last extrusion.
  // A move that extrudes below every height of the current layer starts the next
  // object of a sequential print (Slic3r's "complete objects") at layer 0 again, as
  // Cura numbers them (Toolpath::LayerSequences).
  constexpr double kTolM = 1e-9;
  int layer = ToolpathSegment::kNoLayer;
  double top = 0, bottom = 0;
  size_t first_free = 0;  // the first segment after the last extrusion
  auto& segs = path_.segments;
  for (size_t k = 0; k < segs.size(); ++k) {
    ToolpathSegment& s = segs[k];
    if (!s.LaysBead()) continue;
    const double z0 = s.start_m.z(), z1 = std::max(z0, s.end_m.z());
    if (layer == ToolpathSegment::kNoLayer || z0 > top + kTolM || z0 < bottom - kTolM) {
      const bool first = layer == ToolpathSegment::kNoLayer;
      layer = first || z0 < bottom - kTolM ? 0 : layer + 1;
      if (first) first_free = k;  // moves before the first extrusion stay outside
      top = z1;
      bottom = z0;
    } else {
      top = std::max(top, z1);
    }
    for (size_t j = first_free; j <= k; ++j) segs[j].layer = layer;
    first_free = k + 1;
  }
  for (size_t j = first_free; j < segs.size() && layer != ToolpathSegment::kNoLayer; ++j) segs[j].layer = layer;
  path_.layers_from_z = layer != ToolpathSegment::kNoLayer;
}

std::optional<double> GcodeReader::CommentNumber(std::string_view text, const char* what) const {
  auto v = ParseFiniteNumber(TrimBlanks(text));
  if (!v) Fail(std::string(what) + " comment without a number: \"" + std::string(text) + "\"");
  return v;
}

void GcodeReader::Comment(std::string_view comment) {
  std::string_view c = TrimBlanks(comment);
  auto next_layer = [this] {
    layer_comments_ = true;
    layer_ = layer_ == ToolpathSegment::kNoLayer ? 0 : layer_ + 1;
    stated_height_m_ = 0;
  };
  // A stated height holds for the moves that follow, in this layer; the layer's first is its height.
  auto state_height = [this](double h_m) {
    if (layer_ == ToolpathSegment::kNoLayer) return;
    stated_height_m_ = h_m;
    path_.layer_height_m.emplace(layer_, h_m);
  };
  auto set_type = [this](std::string_view name) {
    std::string type(TrimBlanks(name));
    int index = path_.TypeIndex(type);
    if (index < 0) {
      index = int(path_.type_names.size());
      path_.type_names.push_back(type);
    }
    type_ = index;
  };
  if (StartsWith(c, "LAYER:")) {
    auto v = CommentNumber(c.substr(6), "LAYER");
    if (*v != std::floor(*v) || std::abs(*v) > 1e9) Fail("LAYER comment needs an integer, got " + FormatNumber(*v));
    layer_comments_ = true;
    layer_ = int(*v);
    stated_height_m_ = 0;
  } else if (const std::optional<int> icesl = IceSlLayer(c)) {
    // IceSL: "; <layer 0>" ... "; </layer>" (the end is not read: what follows the
    // last layer's end, the end script, stays in it, as after Cura's last LAYER).
    layer_comments_ = true;
    layer_ = *icesl;
    stated_height_m_ = 0;
  } else if (c == "LAYER_CHANGE" || c == "CHANGE_LAYER") {
    next_layer();
  } else if (c.size() > 6 && StartsWith(c, "layer ") && c[6] >= '0' && c[6] <= '9') {
    next_layer();  // Simplify3D: "; layer 1, Z = 0.200" (counted from 1)
  } else if (StartsWith(c, "BEGIN_LAYER_OBJECT") || StartsWith(c, "BEGIN_LAYER_RAFT")) {
    // KISSlicer: "; BEGIN_LAYER_OBJECT z=0.20 z_thickness=0.20"; a raft's layers below
    // the object's are "; BEGIN_LAYER_RAFT z=0.50" (KISSlicer 1.1: no z_thickness)
    next_layer();
    size_t at = c.find("z_thickness=");
    if (at != std::string_view::npos) {
      std::string_view v = c.substr(at + 12);
      v = v.substr(0, v.find(' '));
      state_height(*CommentNumber(v, "z_thickness") * kMetresPerMm);
    }
  } else if (StartsWith(c, "TYPE:") || StartsWith(c, "FEATURE:") || StartsWith(c, "segType:")) {
    set_type(c.substr(c.find(':') + 1));  // Cura, PrusaSlicer; Bambu, Orca; CraftWare
  } else if (StartsWith(c, "feature ")) {
    set_type(c.substr(8));  // Simplify3D: "; feature outer perimeter"
  } else if (c.size() > 2 && c[0] == '\'' && c.find("',", 1) != std::string_view::npos) {
    set_type(c.substr(1, c.find("',", 1) - 1));  // KISSlicer: "; 'Perimeter Path', 1.2 [feed mm/s], ..."
  } else if (StartsWith(c, "HEIGHT:") || StartsWith(c, "LAYER_HEIGHT:")) {
    double h = *CommentNumber(c.substr(c.find(':') + 1), "HEIGHT");
    // Slicers' comments are in millimetres, whatever G20/G21 say.
    state_height(h * kMetresPerMm);
  } else if (StartsWith(c, "FLAVOR:") &&
             (TrimBlanks(c.substr(7)) == "UltiGCode" || TrimBlanks(c.substr(7)) == "Marlin(Volumetric)")) {
    // Cura's UltiGCode flavour (Ultimaker 2 and 2+) and its "RepRap (Volumetric)"
    // setting, written as Marlin(Volumetric): E is the volume of filament in mm^3 (the
    // printer knows the material's diameter), as under M200; held as lengths of
    // Ultimaker's 2.85 mm filament, or of Marlin's nominal 1.75 mm (the beads' volume
    // does not depend on the choice).
    volumetric_ = true;
    if (volumetric_diameter_mm_ <= 0) {
      volumetric_diameter_mm_ = TrimBlanks(c.substr(7)) == "UltiGCode" ? kUltimakerFilamentMm : kMarlinNominalFilamentMm;
    }
    path_.filament_diameter_m = volumetric_diameter_mm_ * kMetresPerMm;
  } else if (StartsWith(c, "FLAVOR:") && TrimBlanks(c.substr(7)) == "Griffin") {
    // Cura's Griffin flavour is for Ultimaker's own firmware (Ultimaker 3, S3, S5, S7,
    // Factor 4), whose printers all take 2.85 mm filament; the header states volumes
    // (";EXTRUDER_TRAIN.0.MATERIAL.VOLUME_USED:") but no diameter. E is millimetres of it.
    if (path_.filament_diameter_m <= 0) path_.filament_diameter_m = kUltimakerFilamentMm * kMetresPerMm;
  } else if (StartsWith(c, "Layer height:")) {
    path_.header_layer_height_m = *CommentNumber(c.substr(13), "Layer height") * kMetresPerMm;
  } else if (StartsWith(c, "Basic settings: Layer height:")) {
    // Legacy Cura (15.04 and before): ";Basic settings: Layer height: 0.15 Walls: 2 Fill: 10".
    std::string_view v = TrimBlanks(c.substr(29));
    path_.header_layer_height_m = *CommentNumber(v.substr(0, v.find(' ')), "Basic settings: Layer height") * kMetresPerMm;
  } else if (StartsWith(c, "layer_height =")) {
    path_.header_layer_height_m = *CommentNumber(c.substr(14), "layer_height") * kMetresPerMm;
  } else if (StartsWith(c, "layer_thickness_mm =")) {  // KISSlicer
    path_.header_layer_height_m = *CommentNumber(c.substr(20), "layer_thickness_mm") * kMetresPerMm;
  } else if (c == "Software Leveling Applied") {
    // MatterControl writes its measured bed plane (or mesh) into Z: the bed is not at Z 0.
    WarnOncePerName("Software Leveling Applied",
                    "MatterControl applied its software levelling to the file: Z follows the bed it measured (a "
                    "real file's first layer runs at Z 2.15-2.6), not Z 0, so the part stands where that bed is; "
                    "place the bed in the scene (world_from_gcode) to match");
  } else if (StartsWith(c, "layerThickness =")) {  // MatterSlice (MatterControl)
    path_.header_layer_height_m = *CommentNumber(c.substr(16), "layerThickness") * kMetresPerMm;
  } else if (StartsWith(c, "z_layer_height_mm :")) {  // IceSL's settings
    path_.header_layer_height_m = *CommentNumber(c.substr(19), "z_layer_height_mm") * kMetresPerMm;
  } else if (StartsWith(c, "sliceHeight =")) {  // Kiri:Moto's process settings
    path_.header_layer_height_m = *CommentNumber(c.substr(13), "sliceHeight") * kMetresPerMm;
  } else if (StartsWith(c, "layerHeight,")) {  // Simplify3D's settings summary
    path_.header_layer_height_m = *CommentNumber(c.substr(12), "layerHeight") * kMetresPerMm;
  } else if (StartsWith(c, "filament_diameter =")) {
    std::string_view list = c.substr(19);  // "1.75" or "1.75,1.75" (one per extruder)
    path_.filament_diameter_m = *CommentNumber(list.substr(0, list.find(',')), "filament_diameter") * kMetresPerMm;
  } else if (StartsWith(c, "filamentDiameter =")) {  // MatterSlice (MatterControl)
    path_.filament_diameter_m = *CommentNumber(c.substr(18), "filamentDiameter") * kMetresPerMm;
  } else if (StartsWith(c, "Filament Diameter #1:")) {  // ideaMaker: one line per extruder, #1 the first
    path_.filament_diameter_m = *CommentNumber(c.substr(21), "Filament Diameter") * kMetresPerMm;
  } else if (StartsWith(c, "filament_diameter_mm_0 :")) {  // IceSL: one line per extruder, 0 the first
    path_.filament_diameter_m = *CommentNumber(c.substr(24), "filament_diameter_mm_0") * kMetresPerMm;
  } else if (StartsWith(c, "fiber_dia_mm =")) {  // KISSlicer
    path_.filament_diameter_m = *CommentNumber(c.substr(14), "fiber_dia_mm") * kMetresPerMm;
  } else if (StartsWith(c, "filamentDiameters,")) {  // Simplify3D: "1.75|1.75|..." (one per extruder)
    std::string_view list = c.substr(18);
    path_.filament_diameter_m = *CommentNumber(list.substr(0, list.find('|')), "filamentDiameters") * kMetresPerMm;
  }
}

}  // namespace gcode_detail
}  // namespace lt
