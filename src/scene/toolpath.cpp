#include "scene/toolpath.h"

#include <algorithm>
#include <cmath>

namespace lt {

Eigen::Vector3d ToolpathSegment::PointAt(double u) const {
  if (!arc) return start_m + u * (end_m - start_m);
  double r = radius_start_m + u * (radius_end_m - radius_start_m);
  double a = angle_start_rad + u * sweep_rad;
  return Eigen::Vector3d(centre_m.x() + r * std::cos(a), centre_m.y() + r * std::sin(a),
                         start_m.z() + u * (end_m.z() - start_m.z()));
}

Eigen::Vector2d ToolpathSegment::TangentXy(double u) const {
  if (!(xy_length_m > 0)) return Eigen::Vector2d::Zero();
  Eigen::Vector2d d;
  if (!arc) {
    d = (end_m - start_m).head<2>();
  } else {
    double r = radius_start_m + u * (radius_end_m - radius_start_m);
    double a = angle_start_rad + u * sweep_rad;
    Eigen::Vector2d radial(std::cos(a), std::sin(a));
    d = r * sweep_rad * Eigen::Vector2d(-radial.y(), radial.x()) + (radius_end_m - radius_start_m) * radial;
  }
  double n = d.norm();
  return n > 0 ? Eigen::Vector2d(d / n) : Eigen::Vector2d::Zero();
}

size_t Toolpath::SegmentIndexAt(double t_s) const {
  auto it = std::lower_bound(segments.begin(), segments.end(), t_s,
                             [](const ToolpathSegment& s, double t) { return s.t_end_s < t; });
  if (it == segments.end()) return segments.size() - 1;
  return size_t(it - segments.begin());
}

Eigen::Vector3d Toolpath::PositionAt(double t_s) const {
  if (segments.empty()) return Eigen::Vector3d::Zero();
  if (!(t_s > segments.front().t_start_s)) return segments.front().start_m;  // also NaN
  if (t_s >= segments.back().t_end_s) return segments.back().end_m;
  const ToolpathSegment& s = segments[SegmentIndexAt(t_s)];
  double d = s.Duration();
  double u = d > 0 ? std::clamp((t_s - s.t_start_s) / d, 0.0, 1.0) : 1.0;
  return s.PointAt(u);
}

double Toolpath::ExtrudedLength() const {
  double sum = 0;
  for (const auto& s : segments) sum += s.extruded_m;
  return sum;
}

double Toolpath::BeadFilamentLength(bool within_layers) const {
  double sum = 0;
  for (const auto& s : segments) {
    if (s.LaysBead() && (!within_layers || s.layer != ToolpathSegment::kNoLayer)) sum += s.laid_m;
  }
  return sum;
}

double Toolpath::BlobFilamentLength(bool within_layers) const {
  double sum = 0;
  for (const auto& s : segments) {
    if (s.LaysBlob() && (!within_layers || s.layer != ToolpathSegment::kNoLayer)) sum += s.laid_m;
  }
  return sum;
}

double Toolpath::PathLength() const {
  double sum = 0;
  for (const auto& s : segments) sum += s.length_m;
  return sum;
}

namespace {

// Calls visit(first, end) for each run of the extruding moves' layers in print order
// (outside any layer left out), a new run starting where the layer number drops.
template <class Visit>
void ForEachLayerRun(const std::vector<ToolpathSegment>& segments, Visit visit) {
  std::vector<int> layers;
  for (const auto& s : segments) {
    if (s.LaysBead() && s.layer != ToolpathSegment::kNoLayer) layers.push_back(s.layer);
  }
  size_t first = 0;
  for (size_t k = 1; k <= layers.size(); ++k) {
    if (k == layers.size() || layers[k] < layers[k - 1]) {
      visit(layers.begin() + first, layers.begin() + k);
      first = k;
    }
  }
}

}  // namespace

int Toolpath::LayerCount() const {
  int count = 0;
  ForEachLayerRun(segments, [&](auto first, auto end) {
    std::vector<int> run(first, end);
    std::sort(run.begin(), run.end());
    count += int(std::unique(run.begin(), run.end()) - run.begin());
  });
  return count;
}

int Toolpath::LayerSequences() const {
  int runs = 0;
  ForEachLayerRun(segments, [&](auto, auto) { ++runs; });
  return runs;
}

int Toolpath::TypeIndex(const std::string& name) const {
  auto it = std::find(type_names.begin(), type_names.end(), name);
  return it == type_names.end() ? -1 : int(it - type_names.begin());
}

std::string Toolpath::SkippedCommandsNote() const {
  if (skipped_commands.empty()) return "";
  std::vector<std::pair<std::string, size_t>> by_count(skipped_commands.begin(), skipped_commands.end());
  std::stable_sort(by_count.begin(), by_count.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  size_t total = 0;
  for (const auto& [name, n] : by_count) total += n;
  constexpr size_t kNamed = 8;
  std::string note = "skipped " + std::to_string(total) + " command" + (total == 1 ? "" : "s") +
                     " without effect on motion: ";
  for (size_t i = 0; i < by_count.size() && i < kNamed; ++i) {
    note += (i ? ", " : "") + by_count[i].first + " x" + std::to_string(by_count[i].second);
  }
  if (by_count.size() > kNamed) note += " and " + std::to_string(by_count.size() - kNamed) + " other kinds";
  return note;
}

}  // namespace lt
