// The printed part as a scene object that grows over time: the beads a `gcode`
// motion's toolpath has laid down up to each frame's time (scene/bead_geometry.h),
// placed in the world by the motion's world_from_gcode, with a material of its own.
//
// Scene key "print" (docs/scene-format.md): {"material": "pla", "layer_height_mm": 0,
// "filament_diameter_mm": 0, "chunk_moves": 200, "points_per_half_disc": 6}.
//
// Rebuilding only what changed: the toolpath is cut into chunks of about
// chunk_moves moves, each cut made before a move that follows a non-extruding move
// (a travel or retraction), so no bead joint crosses a chunk boundary and the
// chunks' meshes together are exactly BeadMeshUpTo of the whole path. Each chunk is
// one mesh and one instance of the scene geometry. At time t a chunk is empty
// (printing has not reached it), complete (printing has passed it) or growing;
// PrintedPart::UpdateTo rebuilds a chunk's mesh only when that state changes, or
// when it is growing and the time changed: a complete chunk is never rebuilt.
#pragma once

#include <cstddef>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/json_reader.h"
#include "scene/bead_geometry.h"
#include "scene/material.h"
#include "scene/mesh.h"
#include "scene/toolpath.h"

namespace lt {

class EmbreeScene;
class ToolpathOrientation;
struct GcodeMotion;

struct PrintSettings {
  std::string material;            // a key of the scene's "materials"; empty: DefaultPrintMaterial()
  double layer_height_m = 0;       // 0: from the G-code (scene/bead_geometry.h)
  double filament_diameter_m = 0;  // 0: from the G-code, else 1.75 mm
  int points_per_half_disc = 6;    // segments on each rounded side of the bead's cross-section
  int chunk_moves = 200;           // moves per chunk (at least; cut at the next travel)
  void Check() const;              // throws std::invalid_argument
};

// Parses the "print" object (without checking that the motion is "gcode" or that
// the material exists; the scene file does both).
PrintSettings ParsePrintSettings(const json::Value& value);
nlohmann::json PrintSettingsToJson(const PrintSettings& s);

// The bead options of the settings (whole path, no precomputed heights).
BeadOptions BeadOptionsOf(const PrintSettings& s);

// White PLA as the demo scene has it: base colour (0.8, 0.79, 0.75), roughness 0.45,
// subsurface mean free path 0.35/0.3/0.25 mm (R/G/B), 0.35 mm at the laser. Name "print_pla".
Material DefaultPrintMaterial();

struct PrintChunk {
  size_t first_segment = 0, end_segment = 0;  // segments [first, end)
  double t_first_s = 0;  // G-code time the chunk's first extrusion starts (+inf: it extrudes nothing)
  double t_last_s = 0;   // G-code time its last extrusion ends

  enum class State { kEmpty, kGrowing, kComplete };
  // At G-code time t: empty until its first extrusion starts, complete once its
  // last has ended, else growing.
  State StateAt(double gcode_time_s) const {
    if (!(gcode_time_s > t_first_s)) return State::kEmpty;
    return gcode_time_s >= t_last_s ? State::kComplete : State::kGrowing;
  }
};

// The chunks of a toolpath (see above); at least one for a non-empty path.
std::vector<PrintChunk> SplitPrintIntoChunks(const Toolpath& path, int chunk_moves);

// The triangles of the whole part when printing is complete (BeadMeshUpTo at the
// path's end), counted chunk by chunk: memory for one chunk's mesh, not the part's
// (a 38 MB file's 38 M triangles took 5.1 GB built at once).
size_t PrintTrianglesWhenComplete(const Toolpath& path, const PrintSettings& settings);

struct PrintUpdate {
  size_t chunks_rebuilt = 0;
  size_t triangles_rebuilt = 0;  // triangles of the rebuilt chunks' new meshes
  size_t triangles = 0;          // triangles of the whole part after the update
};

class PrintedPart {
 public:
  // chunk_meshes: the SceneGeometry mesh index of each chunk, in chunk order (as
  // LoadSceneGeometry made them; SceneGeometry::print_meshes).
  PrintedPart(const GcodeMotion& motion, const PrintSettings& settings, std::vector<size_t> chunk_meshes);

  size_t chunk_count() const { return chunks_.size(); }
  const std::vector<PrintChunk>& chunks() const { return chunks_; }
  // The G-code time of sequence time t (the motion's start_time_s added).
  double GcodeTime(double sequence_time_s) const;
  // The beads of chunk c at G-code time t, in the G-code frame.
  Mesh ChunkMesh(size_t chunk, double gcode_time_s) const;
  // Chunk c as it stands at G-code time t: empty before its first extrusion,
  // complete after its last, else grown to t.
  Mesh ChunkMeshAt(size_t chunk, double gcode_time_s) const;
  // Brings the chunk meshes of `scene` (built from mutable geometry) to sequence
  // time t, rebuilding only the chunks whose state changed.
  PrintUpdate UpdateTo(EmbreeScene& scene, double sequence_time_s);

 private:
  std::shared_ptr<const ToolpathOrientation> toolpath_;  // holds the path
  const Toolpath* path_ = nullptr;
  double start_time_s_ = 0;
  PrintSettings settings_;
  std::vector<PrintChunk> chunks_;
  std::vector<double> layer_heights_;  // BeadLayerHeights of the path: a chunk's beads need no pass over the path before it
  std::vector<size_t> chunk_meshes_;
  std::vector<std::optional<PrintChunk::State>> state_;  // as built; nullopt: not yet
  std::vector<double> built_time_;  // G-code time a growing chunk was built at
  std::vector<size_t> triangles_;
};

}  // namespace lt
