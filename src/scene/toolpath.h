// A timed toolpath: the nozzle's moves in the order a printer executes them, each
// with its geometry (straight line or arc), the filament it extrudes, its feed
// rate and when it starts and ends. Made by the G-code reader (scene/gcode.h).
//
// Frame and units: the G-code frame (the printer's coordinates: origin and axes of
// the print bed, z up), in metres; times in seconds from the start of the file.
//
// Time model: constant speed, no acceleration (trapezoid-free). A move's duration is
// its path length divided by its feed rate; a move of the extruder alone (retract,
// prime) lasts |filament length| / feed rate; a dwell (G4) lasts what it says.
#pragma once

#include <Eigen/Core>
#include <climits>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace lt {

struct ToolpathSegment {
  static constexpr int kNoLayer = INT_MIN;  // before the first layer comment

  Eigen::Vector3d start_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d end_m = Eigen::Vector3d::Zero();
  double extruded_m = 0;  // filament length fed in (negative: retraction)
  // Of a feed (extruded_m > 0), what leaves the nozzle: the feed first makes up the
  // filament drawn back since the nozzle last laid plastic (retractions, wipes; reset
  // at a tool change), as the filament must refill the nozzle before plastic comes out.
  // A prime in place makes up its retraction; a multi-material unload's cooling moves
  // (+5 mm with the filament 94 mm up the tube) lay nothing. 0 for no feed.
  double laid_m = 0;
  double feed_m_s = 0;    // the feed rate the move ran at (0 for a dwell)
  double t_start_s = 0;
  double t_end_s = 0;
  double length_m = 0;     // path length in space (a helix for an arc that changes z)
  double xy_length_m = 0;  // path length projected on the bed plane
  // The bead height the file states for this move: the last ";HEIGHT:" (PrusaSlicer,
  // which writes one whenever the height changes, a bridge's within its layer),
  // "; LAYER_HEIGHT:" (Bambu Studio, OrcaSlicer) or KISSlicer's z_thickness since the
  // move's layer began; 0 when none (and outside any layer).
  double height_m = 0;
  // From ;LAYER:n (Cura), counted layer-change comments (PrusaSlicer, Simplify3D, ...),
  // or, in a file without layer comments, from the heights it extrudes at
  // (Toolpath::layers_from_z).
  int layer = kNoLayer;
  int type = -1;           // index into Toolpath::type_names (last ;TYPE: comment), -1 before any
  // The command that made it: 0, 1, 2, 3 (arcs), 4 (dwell), 10 and 11 (firmware
  // retraction and recovery, with their Z hop), 28 (home).
  int gcode = 1;
  int line = 0;            // 1-based line in the G-code file

  // Arcs (gcode 2 or 3) in the bed plane: the point at parameter u in [0, 1] is
  // centre + r(u) (cos a(u), sin a(u)) with r(u) = radius_start + u (radius_end -
  // radius_start) and a(u) = angle_start + u sweep; z is linear in u. sweep > 0 is
  // counter-clockwise seen from +z (G3), < 0 clockwise (G2).
  bool arc = false;
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();
  double radius_start_m = 0;
  double radius_end_m = 0;
  double angle_start_rad = 0;
  double sweep_rad = 0;

  double Duration() const { return t_end_s - t_start_s; }
  bool Extrudes() const { return extruded_m > 0; }
  // Lays plastic while moving across the bed: a bead (not a prime in place, not a Z move,
  // not a feed that only makes up an earlier retraction).
  bool LaysBead() const { return laid_m > 0 && xy_length_m > 0; }
  // Lays plastic without moving across the bed (a feed in place, or with Z alone, beyond
  // what makes up a retraction: Cura's clay start of a layer, a deliberate blob, a prime
  // with extra length): a blob, which is in no bead (a bead needs a path; the blob's
  // shape is the material's and the surface's, not the file's).
  bool LaysBlob() const { return laid_m > 0 && !(xy_length_m > 0); }
  // The point at parameter u in [0, 1] (linear in path length for lines and arcs of
  // constant radius; u = 0 is start_m, u = 1 is end_m).
  Eigen::Vector3d PointAt(double u) const;
  // The unit direction of motion in the bed plane at u; zero when the move has no
  // motion in the bed plane (z only, extruder only, dwell).
  Eigen::Vector2d TangentXy(double u) const;
};

// Something the file asks that the reader could only approximate (a relative move
// from a position probing left unknown, an axis it does not model, an unclosed
// comment): the first line it happened on, how many times, and what was done.
struct ToolpathWarning {
  int line = 0;
  int count = 0;
  std::string text;
};

struct Toolpath {
  std::vector<ToolpathSegment> segments;  // in time order, contiguous in time and space
  std::vector<std::string> type_names;    // the distinct ;TYPE: names, in order of appearance
  std::map<std::string, size_t> skipped_commands;  // commands without effect on motion: count each
  // Layer heights stated in the file: the first ";HEIGHT:h" (PrusaSlicer) of each
  // layer (later ones in the layer, a bridge's, hold for the moves after them:
  // ToolpathSegment::height_m), and the header's ";Layer height: h" (Cura) or "; layer_height = h" (PrusaSlicer); 0 when absent.
  std::map<int, double> layer_height_m;
  double header_layer_height_m = 0;
  double filament_diameter_m = 0;  // "; filament_diameter = d" (PrusaSlicer), 0 when absent
  // Moves (G0-G3) before the file's first F, timed at the firmware's power-on feed
  // rate, and the line of the first of them.
  int moves_at_power_on_feed = 0;
  int first_power_on_feed_line = 0;
  // Layers numbered from the extrusion heights (the file has no layer comments).
  bool layers_from_z = false;
  // Firmware retraction: G10 and G11 commands (repeats included), the line of the
  // first, and whether the file set their length and speeds (M207); without it they
  // run with Marlin's defaults (3 mm at 45 mm/s, recovered at 8 mm/s, no Z hop).
  int firmware_retractions = 0;
  int firmware_recoveries = 0;
  int swap_retractions = 0;  // of the G10: swap retractions (Marlin's G10 S1; 13 mm by default)
  int first_firmware_retraction_line = 0;
  bool firmware_retraction_set = false;
  // The program's end (M2, M30; 0: none) and the lines after it holding commands or
  // other text, which were not read.
  int program_end_line = 0;
  std::string program_end_command;
  int lines_after_program_end = 0;
  // Approximations, one per kind, in order of their first line (`info` and `render`
  // print them as "file:line: text").
  std::vector<ToolpathWarning> warnings;

  double Duration() const { return segments.empty() ? 0.0 : segments.back().t_end_s; }
  // The segment running at time t: the first whose end is >= t (clamped to the
  // first and last). Requires a non-empty path.
  size_t SegmentIndexAt(double t_s) const;
  // The nozzle position at time t, clamped to the start and end of the path (the
  // origin for an empty path).
  Eigen::Vector3d PositionAt(double t_s) const;
  // Sums over all segments: the net filament fed in (retractions subtract, so a
  // retract and its re-prime cancel) and the distance travelled.
  double ExtrudedLength() const;
  // The filament the beads take (ToolpathSegment::laid_m of the moves that LaysBead: not
  // the retractions, primes and wipes), all of them or only those inside a layer (not a
  // start script's purge lines before the first layer): what a slicer's "filament used"
  // counts.
  double BeadFilamentLength(bool within_layers) const;
  // The filament laid in place (ToolpathSegment::LaysBlob), all or inside a layer: with
  // BeadFilamentLength, every positive feed that makes up no retraction.
  double BlobFilamentLength(bool within_layers) const;
  double PathLength() const;
  // Layers printed: the distinct layers among the moves that lay beads (outside any
  // layer counts as none), counted in each run of them that LayerSequences finds.
  int LayerCount() const;
  // Runs of layers in print order, a new run starting where the layer number drops:
  // 1 for a print made layer by layer; one per object for objects printed one after
  // another from the bed up (Cura's "one at a time" numbers ;LAYER: from 0 again for
  // each object); 0 without layers.
  int LayerSequences() const;
  // Index of a type name in type_names, -1 when absent.
  int TypeIndex(const std::string& name) const;
  // "skipped N commands without effect on motion: M104 x3, M106 x2, ..." (the
  // most frequent first, at most 8 named); empty when none were skipped.
  std::string SkippedCommandsNote() const;
};

}  // namespace lt
