// Reading G-code as slicers write it (Cura, PrusaSlicer and its forks, Simplify3D,
// KISSlicer, ideaMaker, CraftWare, Slic3r; Marlin, RepRapFirmware and Klipper
// flavours) into a timed toolpath (scene/toolpath.h).
//
// Understood, everything else skipped and counted per command (Toolpath::
// skipped_commands: temperatures, fans, accelerations, T tool changes, ...):
//   G0, G1          straight moves (X Y Z E F; A or B instead of E: the extruder axes of
//                   the Mach3/Machinekit and MakerBot flavours, each with its own
//                   position); RepRapFirmware's H1, H3, H4 (towards the
//                   endstops: the named axes home to 0, a move tagged 28 laying nothing)
//                   and H2 (motors without kinematics: the same move on a Cartesian
//                   printer); E with H1-H4 is an error
//   X.. Y.. Z..     axis words without a command (legacy Cura start scripts' "Z10"): the
//                   last G0-G3 again (RS-274's modal motion; warned, as Marlin without
//                   GCODE_MOTION_MODES ignores such a line); an error before any G0-G3
//                   or after G80 on a line with other commands
//   G2, G3          arcs clockwise / counter-clockwise in the XY plane, centre by I/J
//                   offsets from the start, or radius R (R < 0: the arc over 180 degrees);
//                   Z changing along the arc makes a helix; I/J with end = start is a
//                   full circle; P n: n turns (the arc as given and n - 1 full turns
//                   more; Bambu Studio's and OrcaSlicer's spiral lift "G2 Z I J P1")
//   G4              dwell (P milliseconds or S seconds)
//   G10, G11        firmware retraction and recovery (G10 without parameters; G10 L2
//                   and L20 set work offsets; other parameters (tool offsets,
//                   temperatures) are skipped), by
//                   M207's S length, F feed, Z hop, R extra and T recovery feed, else
//                   Marlin's defaults (3 mm at 45 mm/s, recovered at 8 mm/s)
//   G17, G18, G19   the arcs' plane: XY (I, J), ZX (K, I), YZ (J, K); an arc outside XY
//                   becomes straight chords within 1 um of it (the toolpath's arcs are XY)
//   G20, G21        inches / millimetres
//   G28             home: the named axes (all when none named) to 0, one after another
//                   (X, Y, Z) at Marlin's homing speeds (50, 50, 4 mm/s), not the modal F
//   G90, G91        absolute / relative X Y Z, and E relative under G91 (below)
//   G92             set the current position (no motion); no axes: all axes to 0;
//                   G92.1 clears its offset, G92.2 clears and keeps it, G92.3 restores it;
//                   on an axis whose place is unknown (G161/G162, M132, probing) it
//                   states the place: no offset, the next absolute move goes there
//   G161, G162      MakerBot's and Sailfish's homing to the minimum / maximum endstops,
//                   M132 their stored home offsets: the named axes (all when none named)
//                   unknown until G92 or an absolute move (warned; no time)
//   M101, M103      extruder on / off: skipped; in a file that never gives E (Skeinforge
//                   for a DC extruder) the moves between them are warned: no bead
//   G53             machine coordinates (no G92 or work offset) for the rest of its line
//   G54-G59.3       work coordinate systems, their origins set by G10 L2 (machine
//                   coordinates) or G10 L20 (the current position's value); P0: active
//   M290            babystepping (X, Y, Z or S; R0 absolute): moves now and shifts
//                   later moves until the axis is homed
//   M82, M83        absolute / relative E; E is relative under G91 or after M83
//                   (Klipper's rule; Marlin's too, except that its G90 also ends M83)
//   M2, M30         program end: later lines are not read, only counted ("M30 name",
//                   Marlin's SD file delete, is skipped)
//   M200            volumetric extrusion: D diameter (D0 off), S0/S1 off/on; E in mm^3,
//                   held as the length of that diameter's filament (Marlin's rules)
//   M207            firmware retraction settings; M208 (Marlin) S extra length and
//                   F feed on recovery (with axis words, RepRapFirmware's limits: skipped)
//   M220, M221      feed rate and flow percentages (S; M220 B/R save and restore),
//                   scaling the feed and the E of later G0-G3 moves
//   T n             the active tool (its M221 flow; E's axis in MakerBot's reading); so
//                   do MakerBot's M135 T n, M6 T n and ReplicatorG's M108 T n. Feeds in
//                   place after a change, before the tool's first bead, refill its nozzle
//   M605 S2-S4      an IDEX printer's duplication or mirror mode: warned (the second
//                   carriage's copy is not in the toolpath)
// A feed in place beyond what makes up a retraction is a blob: no bead, counted
// (Toolpath::BlobFilamentLength), warned when it lies within a layer.
//   F               feed rate in mm/min (inch/min under G20), modal, shared by G0-G3
//   G29, G30, G32-G35, G38.2-5, G380 (Bambu), M48, G80 alone on its line (Prusa), Klipper's
//                   BED_MESH_CALIBRATE etc. (probing: warned, it takes no time here);
//                   Marlin's G12 clean and G27 park, Griffin's G280 prime, Prusa XL's P0 park and T.. D0: X, Y,
//                   Z unknown until an absolute move or homing sets each (a relative
//                   move on an unknown axis is warned: Toolpath::warnings; so is a bead
//                   laid while an axis is unknown, at its last known value). G29 that only
//                   loads, fills, activates or saves a mesh (S1-S3, A, L, P3, ...) is skipped
//   G29.1 Z         Bambu's z-trim: an offset of later moves (M221 X Y Z, Bambu's soft
//                   endstops, is skipped)
//   U, V, W, C      extra axes on G0-G3, G92, G28: ignored with a warning; one moving
//                   on an extruding line is an error
//   SET_RETRACTION  Klipper's firmware retraction settings (mm, mm/s)
//   SET_GCODE_OFFSET  Klipper's offset of later absolute moves (X, Y, Z, *_ADJUST; MOVE=1)
// Comments: ;LAYER:n (Cura) sets the layer; ;LAYER_CHANGE (PrusaSlicer) starts the
// next layer (0 first); ;TYPE:name names what follows (WALL-OUTER, External
// perimeter, ...); ;HEIGHT:h (PrusaSlicer) the layer height; header ";Layer height:"
// (Cura), "; layer_height =" and "; filament_diameter =" (PrusaSlicer); Bambu Studio's
// and OrcaSlicer's "; CHANGE_LAYER", "; FEATURE: name" and "; LAYER_HEIGHT: h" are
// read as LAYER_CHANGE, TYPE: and HEIGHT:; Simplify3D's "; layer 1, Z = 0.2" and
// KISSlicer's "; BEGIN_LAYER_OBJECT z=.. z_thickness=h" (and a raft's "; BEGIN_LAYER_RAFT
// z=..") start the next layer (with height h); Simplify3D's "; feature name", KISSlicer's "; 'Name Path', ..." and
// CraftWare's ";segType:name" name the type; header "layerHeight,", "filamentDiameters,"
// (Simplify3D), "layer_thickness_mm =", "fiber_dia_mm =" (KISSlicer), "sliceHeight ="
// (Kiri:Moto), "Filament Diameter #1:" (ideaMaker), "layerThickness =",
// "filamentDiameter =" (MatterSlice); ";FLAVOR:Griffin" (Cura for Ultimaker 3 and S-series):
// 2.85 mm filament unless the file states another; ";FLAVOR:UltiGCode" (Cura for Ultimaker 2): E in mm^3, held as lengths of
// 2.85 mm filament; ";FLAVOR:Marlin(Volumetric)" (Cura's RepRap (Volumetric)): E in
// mm^3, held as lengths of Marlin's nominal 1.75 mm filament. Comments hold
// millimetres under G20 too. A file without any layer comment takes its layers from
// the heights it extrudes at (Toolpath::layers_from_z). Structured
// comments count only on lines holding nothing else. Line numbers (N) are dropped; a
// checksum (*n) must match the line's bytes before it; parenthesised comments are
// dropped (a ';' or '*' inside one is part of it, a '(' nests: Skeinforge's settings; one without ')' runs to the end of
// the line, warned), and so are a quoted string's and
// a message's or file name's (M23, M117, ...; unless only a checksum follows '*');
// a parameter may be a quoted string (RepRapFirmware's G29 S1 P"heightmap.csv": a word
// without a number); M98 P"file.g" (a RepRapFirmware macro file) is skipped and warned
// once per file; letters may be lower case; G5 (Bezier) is an error, a bare G5 (Anycubic's
// power-loss resume) is skipped. A UTF-8
// byte order mark, LF, CR LF and lone CR line ends (mixed too) and "%" lines (RS-274's
// program marks) are accepted.
//
// The machine starts at the origin with E = 0, absolute XYZ, E following G90/G91,
// no feed rate: moves before the first F run at Marlin's power-on feed rate,
// 1500 mm/min (counted in Toolpath::moves_at_power_on_feed).
//
// Extended commands (a first word of letters, digits and underscores, not a letter
// and a number: Klipper's PRINT_START, EXCLUDE_OBJECT_START NAME=..., which
// OrcaSlicer and PrusaSlicer write for Klipper printers) are skipped and counted
// by name, as the firmware-only M and G commands are; one that is not Klipper's own
// motionless command (a user's macro) is warned about once per name. Lines starting
// with '@' are host commands (OctoPrint's @pause): skipped. Probing is warned about
// (it takes no time here).
//
// A binary G-code file (PrusaSlicer's .bgcode, magic "GCDE") or a zip archive (a
// .gcode.3mf) is refused as such, naming the file. Errors are lt::InputError naming "file:line": a NUL byte (not a text file), a letter without a number, a number
// that is not finite or malformed, several values for one letter (RepRapFirmware's
// "E0.1:0.2", amounts per drive), a parameter the command does not take or given
// twice, F <= 0, a checksum that does not match, an M207 or M208 length < 0 or feed <= 0,
// an M220 percentage <= 0 or M221 < 0, an arc
// without I/J or R, with both,
// with zero radius, a P that is not a whole number of turns from 1 to 100, whose end is not on its circle (0.01 mm + 0.1 % of the radius),
// or an R arc whose chord is longer than its diameter.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "scene/toolpath.h"

namespace lt {

// Parses G-code text; errors name `display_name`:line.
Toolpath ParseGcode(std::string_view text, const std::string& display_name);
// Reads a G-code file; errors name it as `display_name` (default: the path).
Toolpath ReadGcode(const std::filesystem::path& path, const std::string& display_name = "");

}  // namespace lt
