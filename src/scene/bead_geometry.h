// The printed part as it grows: a triangle mesh of the beads a toolpath has laid
// down up to time t, in the G-code frame (metres).
//
// Every move that extrudes (filament fed in, motion in the bed plane) lays a bead
// along its path. Its volume is the filament's: pi (d/2)^2 * extruded length (d the
// filament diameter). Its cross-section, in the vertical plane across the path, has
// the layer's height h, its top at the nozzle tip, and the area A = volume / path
// length in the bed plane, as
//   a stadium (a rectangle with half-disc ends, the usual slicer model) of width
//   w = A / h + h (1 - pi / 4) when that is at least h,
//   an ellipse of height h and width 4 A / (pi h) otherwise (under-extrusion).
// The polygon approximating the cross-section is widened so its area is exactly A
// (by a factor 1 / ((m / pi) sin(pi / m)) on an ellipse of 2m points, m = n + 1 for n
// points per half disc: 2.1 % with the default n = 8; less on a stadium): the mesh holds the extruded volume, up to float rounding
// and the merging of nearly equal joined cross-sections (below). A bead
// that rises along its path (a helix, spiral vase mode) is approximated: its mitred
// joints keep the cross-section level, which adds a little (0.08 % on a helix rising
// 1 mm per turn of radius 10 mm).
//
// Consecutive beads join: at a turn of up to 90 degrees (and where the mitre fits in
// both moves) the two meet on the mitre plane, the cross-section widened there by
// 1 / cos(turn / 2) so the bead keeps its width; a step in cross-section between moves
// that extrude at different rates is closed by a flat ring (cross-sections within
// 0.01 % of the previous one, or whose widths differ by less than 16 float spacings at
// that distance from the origin, are taken equal: the step would not hold in float
// coordinates). Elsewhere (sharper turns,
// travel, retraction, a layer change) a bead ends in a flat cap. Arcs are cut into
// chords of at most 10 degrees, each with its share of the volume. Each run of joined
// beads is a closed surface (outward normals, counter-clockwise triangles).
//
// Layer height, first found of: BeadOptions::layer_height_m; the height the file states
// for the move (ToolpathSegment::height_m: PrusaSlicer's last ;HEIGHT, a bridge's too); the move's height above the previous, lower level at which
// the path extruded (the bed, z = 0, below the first); the file's header layer height.
// Extrusion without motion in the bed plane (priming in place) lays no bead.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "scene/mesh.h"
#include "scene/toolpath.h"

namespace lt {

struct BeadOptions {
  double filament_diameter_m = 0;  // 0: the file's "; filament_diameter" or else 1.75 mm
  double layer_height_m = 0;       // 0: from the file (see above)
  int points_per_half_disc = 8;    // segments on each rounded end of the cross-section
  uint32_t material = 0;           // material index of every triangle
  // Only the beads of segments [first_segment, end_segment) (layer heights still
  // come from the whole path before them). A range that starts after a move that
  // does not extrude breaks no joint: such ranges partition the full mesh.
  size_t first_segment = 0;
  size_t end_segment = SIZE_MAX;
  // The path's BeadLayerHeights with these options, or null. Given, the beads of
  // [first_segment, end_segment) are built from it without passing over the
  // segments before first_segment for their levels (a part cut into many chunks
  // would otherwise pass over the path once per chunk).
  const std::vector<double>* layer_heights = nullptr;
  // Throws std::invalid_argument for negative or non-finite sizes or fewer than 2 points.
  void Check() const;
};

struct BeadStats {
  size_t beads = 0;             // moves (or parts of a move) that laid a bead
  size_t runs = 0;              // runs of joined beads (closed surfaces)
  size_t skipped = 0;           // extruding moves with no positive layer height found
  double volume_m3 = 0;         // the extruded volume the mesh holds
};

// The beads laid from the start of the toolpath up to time t (a move under way at t
// contributes the part done, with its share of the filament). Empty (no vertices)
// before the first extrusion.
Mesh BeadMeshUpTo(const Toolpath& path, double t_s, const BeadOptions& options = {}, BeadStats* stats = nullptr);

// The layer height BeadMeshUpTo gives each segment's bead (see above; 0 where the
// segment lays no bead or no height is found), whatever the time: a segment's height
// depends only on the segments before it. One entry per segment.
std::vector<double> BeadLayerHeights(const Toolpath& path, const BeadOptions& options = {});

// Volume enclosed by a mesh of closed surfaces with outward normals (divergence
// theorem, in double, about the centre of the mesh's bounds).
double MeshVolume(const Mesh& mesh);

}  // namespace lt
