#include "scene/printed_part.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "scene/bead_geometry.h"
#include "scene/embree_scene.h"
#include "scene/motion_gcode.h"

namespace lt {

using json::Range;

void PrintSettings::Check() const {
  if (!(std::isfinite(layer_height_m) && layer_height_m >= 0)) throw std::invalid_argument("print: layer height must be >= 0");
  if (!(std::isfinite(filament_diameter_m) && filament_diameter_m >= 0)) {
    throw std::invalid_argument("print: filament diameter must be >= 0");
  }
  if (points_per_half_disc < 2) throw std::invalid_argument("print: points_per_half_disc must be >= 2");
  if (chunk_moves < 1) throw std::invalid_argument("print: chunk_moves must be >= 1");
}

PrintSettings ParsePrintSettings(const json::Value& value) {
  json::Object o(value);
  PrintSettings s;
  s.material = o.String("material", "");
  if (auto m = o.Find("material"); m && s.material.empty()) m->Fail("must not be empty (omit it for the default PLA)");
  s.layer_height_m = 1e-3 * o.Number("layer_height_mm", 0.0, Range::NonNegative());
  s.filament_diameter_m = 1e-3 * o.Number("filament_diameter_mm", 0.0, Range::NonNegative());
  s.points_per_half_disc = int(o.Integer("points_per_half_disc", 6, Range::Closed(2, 64)));
  s.chunk_moves = int(o.Integer("chunk_moves", 200, Range::Closed(1, 1e9)));
  o.Finish();
  return s;
}

nlohmann::json PrintSettingsToJson(const PrintSettings& s) {
  nlohmann::json j = {{"layer_height_mm", s.layer_height_m * 1e3},
                      {"filament_diameter_mm", s.filament_diameter_m * 1e3},
                      {"points_per_half_disc", s.points_per_half_disc},
                      {"chunk_moves", s.chunk_moves}};
  if (!s.material.empty()) j["material"] = s.material;
  return j;
}

Material DefaultPrintMaterial() {
  Material m;
  m.name = "print_pla";
  m.base_color = Eigen::Vector3f(0.8f, 0.79f, 0.75f);
  m.metallic = 0;
  m.roughness = 0.45f;
  Subsurface sub;
  sub.mean_free_path_m = Eigen::Vector3d(0.35e-3, 0.3e-3, 0.25e-3);
  sub.mean_free_path_laser_m = 0.35e-3;
  m.subsurface = sub;
  return m;
}

BeadOptions BeadOptionsOf(const PrintSettings& s) {
  BeadOptions o;
  o.layer_height_m = s.layer_height_m;
  o.filament_diameter_m = s.filament_diameter_m;
  o.points_per_half_disc = s.points_per_half_disc;
  return o;
}

std::vector<PrintChunk> SplitPrintIntoChunks(const Toolpath& path, int chunk_moves) {
  if (chunk_moves < 1) throw std::invalid_argument("SplitPrintIntoChunks: chunk_moves must be >= 1");
  std::vector<PrintChunk> chunks;
  const auto& segs = path.segments;
  size_t first = 0;
  for (size_t k = 1; k <= segs.size(); ++k) {
    const bool at_end = k == segs.size();
    // A cut before segment k breaks no bead joint when segment k-1 does not extrude.
    const bool can_cut = at_end || !segs[k - 1].LaysBead();
    if (at_end || (can_cut && k - first >= size_t(chunk_moves))) {
      PrintChunk c;
      c.first_segment = first;
      c.end_segment = k;
      c.t_first_s = std::numeric_limits<double>::infinity();
      c.t_last_s = -std::numeric_limits<double>::infinity();
      for (size_t i = first; i < k; ++i) {
        if (!segs[i].LaysBead()) continue;
        c.t_first_s = std::min(c.t_first_s, segs[i].t_start_s);
        c.t_last_s = std::max(c.t_last_s, segs[i].t_end_s);
      }
      chunks.push_back(c);
      first = k;
    }
  }
  return chunks;
}

size_t PrintTrianglesWhenComplete(const Toolpath& path, const PrintSettings& settings) {
  settings.Check();
  BeadOptions o = BeadOptionsOf(settings);
  const std::vector<double> heights = BeadLayerHeights(path, o);
  o.layer_heights = &heights;
  size_t triangles = 0;
  for (const PrintChunk& c : SplitPrintIntoChunks(path, settings.chunk_moves)) {
    o.first_segment = c.first_segment;
    o.end_segment = c.end_segment;
    triangles += BeadMeshUpTo(path, path.Duration(), o).TriangleCount();
  }
  return triangles;
}

PrintedPart::PrintedPart(const GcodeMotion& motion, const PrintSettings& settings, std::vector<size_t> chunk_meshes)
    : toolpath_(motion.toolpath), start_time_s_(motion.start_time_s), settings_(settings),
      chunk_meshes_(std::move(chunk_meshes)) {
  if (!toolpath_) throw std::invalid_argument("PrintedPart: the motion has no toolpath");
  settings_.Check();
  path_ = &toolpath_->path();
  chunks_ = SplitPrintIntoChunks(*path_, settings_.chunk_moves);
  layer_heights_ = BeadLayerHeights(*path_, BeadOptionsOf(settings_));
  if (chunk_meshes_.size() != chunks_.size()) {
    throw std::invalid_argument("PrintedPart: " + std::to_string(chunk_meshes_.size()) + " meshes for " +
                                std::to_string(chunks_.size()) + " chunks");
  }
  state_.assign(chunks_.size(), std::nullopt);
  built_time_.assign(chunks_.size(), 0.0);
  triangles_.assign(chunks_.size(), 0);
}

double PrintedPart::GcodeTime(double sequence_time_s) const {
  return std::clamp(start_time_s_ + sequence_time_s, 0.0, path_->Duration());
}

Mesh PrintedPart::ChunkMesh(size_t chunk, double gcode_time_s) const {
  const PrintChunk& c = chunks_.at(chunk);
  BeadOptions o = BeadOptionsOf(settings_);
  o.first_segment = c.first_segment;
  o.end_segment = c.end_segment;
  o.layer_heights = &layer_heights_;
  Mesh mesh = BeadMeshUpTo(*path_, gcode_time_s, o);
  mesh.name = "print/chunk_" + std::to_string(chunk);
  return mesh;
}

Mesh PrintedPart::ChunkMeshAt(size_t chunk, double gcode_time_s) const {
  const PrintChunk& c = chunks_.at(chunk);
  if (c.StateAt(gcode_time_s) != PrintChunk::State::kEmpty) return ChunkMesh(chunk, std::min(gcode_time_s, c.t_last_s));
  Mesh empty;
  empty.name = "print/chunk_" + std::to_string(chunk);
  return empty;
}

PrintUpdate PrintedPart::UpdateTo(EmbreeScene& scene, double sequence_time_s) {
  const double t = GcodeTime(sequence_time_s);
  PrintUpdate u;
  for (size_t c = 0; c < chunks_.size(); ++c) {
    const PrintChunk& chunk = chunks_[c];
    const PrintChunk::State want = chunk.StateAt(t);
    const bool rebuild = state_[c] != want || (want == PrintChunk::State::kGrowing && built_time_[c] != t);
    if (rebuild) {
      Mesh mesh = ChunkMeshAt(c, t);
      triangles_[c] = mesh.TriangleCount();
      u.triangles_rebuilt += triangles_[c];
      ++u.chunks_rebuilt;
      scene.ReplaceMesh(chunk_meshes_[c], std::move(mesh));
      state_[c] = want;
      built_time_[c] = t;
    }
    u.triangles += triangles_[c];
  }
  return u;
}

}  // namespace lt
