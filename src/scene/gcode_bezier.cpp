// The G-code reader's G5: Marlin's cubic Bezier move (BEZIER_CURVE_SUPPORT), run as
// straight chords.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "scene/gcode_reader.h"

namespace lt {
namespace gcode_detail {

void GcodeReader::Bezier() {
  // "G5 I J P Q X Y E F": a cubic Bezier curve in the XY plane from the current position
  // to X Y, its first control point at the start plus I J, its second at the end plus
  // P Q (each 0 when absent, as Marlin's parser.linearval gives). Marlin steps the curve's
  // parameter t and moves Z and E linearly in t (cubic_b_spline); so do the chords here,
  // each off the curve by at most kChordSagittaMm. Before, G5 was refused (skipped, the
  // path would have gone on from the curve's start).
  const std::string command = "G5";
  if (plane_ != 17) Fail("G5 (Bezier move) needs the XY plane (G17), as Marlin does; G" + std::to_string(plane_) + " is set");
  Expect("XYZEFIJPQABUVWCS", command);
  MoveS(command);
  SetFeed();
  NoteEWords();
  NoteExtruderAxes();
  TrackKnownAxes(command, 3);  // I J P Q are relative to the start and the end, as arcs' I J
  const Eigen::Vector3d start = pos_mm_, end = Target();
  auto offset = [&](char letter) {
    const Word* w = Find(letter);
    return w ? *w->value * unit_mm_ : 0.0;
  };
  const Eigen::Vector2d p0 = start.head<2>(), p3 = end.head<2>();
  const Eigen::Vector2d p1 = p0 + Eigen::Vector2d(offset('I'), offset('J'));
  const Eigen::Vector2d p2 = p3 + Eigen::Vector2d(offset('P'), offset('Q'));
  auto point = [&](double t) {
    const double u = 1 - t;
    return Eigen::Vector2d(u * u * u * p0 + 3 * u * u * t * p1 + 3 * u * t * t * p2 + t * t * t * p3);
  };
  // A polyline of N equal steps in t lies within max|B''| / (8 N^2) of the curve, and
  // |B''| <= 6 max(|p0 - 2 p1 + p2|, |p1 - 2 p2 + p3|).
  const double bend = 6 * std::max((p0 - 2 * p1 + p2).norm(), (p1 - 2 * p2 + p3).norm());
  if (!std::isfinite(bend)) Fail("G5 control points I J / P Q are too far to compute the curve");
  const int chords = int(std::min(kMaxChords, std::max(1.0, std::ceil(std::sqrt(bend / (8 * kChordSagittaMm))))));
  std::vector<Eigen::Vector3d> points;
  double xy_length = 0, length = 0;
  Eigen::Vector3d last = start;
  for (int k = 1; k <= chords; ++k) {
    const double t = double(k) / chords;
    Eigen::Vector3d q = end;
    if (k < chords) q << point(t), start.z() + t * (end.z() - start.z());
    xy_length += (q - last).head<2>().norm();
    length += (q - last).norm();
    points.push_back(q);
    last = q;
  }
  const double extruded = Extruded();
  WarnBeadAtUnknown(command, extruded, xy_length);
  ExtraAxes(command, extruded);
  const double feed = MoveFeed(length, extruded);
  for (const Eigen::Vector3d& q : points) {
    const Eigen::Vector3d step = q - pos_mm_;
    AddSegment(5, q, extruded / chords, step.norm(), step.head<2>().norm(), nullptr, feed);
  }
}

}  // namespace gcode_detail
}  // namespace lt
