// Gap resolution experiment (docs/experiments.md, "Gap resolution"): measures
// the slot widths of the slot test part in scanned runs and compares them with
// the part's geometry.
//
//   exp_gap OUT_DIR PART_GLB LABEL=RUN_DIR [LABEL=RUN_DIR ...]
//
// For every laser frame of every run, the triangulated stripe points
// (centers/NNNNNN.csv, world frame) and, for reference, the renderer's exact
// stripe centres (gt/NNNNNN_centers.csv) are read as a profile across the
// slots, one point per image column. A slot shows as a run of columns whose
// points lie below half the slot depth, or that have no point, between columns
// on the top surface (within a quarter of the slot depth of it; at least two
// columns wide). Its edges are where the profile crosses half the slot
// depth (linear interpolation between the last top point and the first low
// point; half a column beyond the top point when the neighbouring column has
// no point), as the thesis measured its gaps across the middle of the gap.
// Each true slot (from the part's mesh: its walls are the faces with normals
// along +-x) is measured in the frame where it lies nearest the image centre;
// it is "detected" when exactly one measured gap has its centre inside the
// slot, and a frame's measured gaps that match no slot count as false gaps.
//
// Writes OUT_DIR/gap_resolution.csv (label, true width, measured width from
// the scan and from the truth centres, errors, detected) and
// OUT_DIR/gap_resolution.svg (measured vs true width, and relative error).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>

#include "core/atomic_file.h"
#include "exp_common.h"
#include "core/error.h"
#include "pipeline/ground_truth.h"
#include "pipeline/run_folder_reader.h"
#include "pipeline/scan_output.h"
#include "pipeline/svg_plot.h"
#include "scene/gltf_loader.h"

namespace lt {
namespace {

namespace fs = std::filesystem;

struct Slot {
  double x0, x1;  // walls, world x (m)
  double width() const { return x1 - x0; }
  double center() const { return 0.5 * (x0 + x1); }
};

struct PartGeometry {
  std::vector<Slot> slots;
  double top_z = 0, bottom_z = 0;  // top surface and slot bottoms (m)
};

// Slot walls: faces with normals along x that do not reach z = 0. A slot's
// left wall faces +x (into the slot) and its right wall -x; the upper parts of
// the plate's end faces (which face outwards) are the first and last walls.
PartGeometry ReadPart(const fs::path& glb) {
  GltfAsset asset = LoadGltf(glb);
  std::vector<std::pair<double, int>> walls;  // x, facing sign
  PartGeometry part;
  part.top_z = -INFINITY;
  part.bottom_z = INFINITY;
  for (const GltfInstance& inst : asset.instances) {
    const Mesh& m = asset.meshes[inst.mesh];
    for (size_t t = 0; t < m.TriangleCount(); ++t) {
      Eigen::Vector3d p[3];
      for (int k = 0; k < 3; ++k) p[k] = inst.file_from_mesh * m.positions[m.indices[3 * t + k]].cast<double>();
      part.top_z = std::max({part.top_z, p[0].z(), p[1].z(), p[2].z()});
      Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]).normalized();
      double zmin = std::min({p[0].z(), p[1].z(), p[2].z()});
      if (std::abs(n.x()) > 0.999 && zmin > 1e-6) walls.push_back({p[0].x(), n.x() > 0 ? 1 : -1});
    }
  }
  std::sort(walls.begin(), walls.end());
  walls.erase(std::unique(walls.begin(), walls.end(),
                          [](const auto& a, const auto& b) { return std::abs(a.first - b.first) < 1e-7; }),
              walls.end());
  if (walls.size() < 4 || walls.front().second != -1 || walls.back().second != 1)
    throw InputError(glb.string(), "not a slot test part (no outward end faces)");
  for (size_t i = 1; i + 2 < walls.size(); i += 2) {
    if (walls[i].second != 1 || walls[i + 1].second != -1) throw InputError(glb.string(), "cannot pair the slot walls");
    part.slots.push_back({walls[i].first, walls[i + 1].first});
  }
  // Slot bottoms: the height of the end faces' upper parts' lower edge is not
  // known here; take it from the part's thickness minus the slot depth found on
  // the walls' triangles.
  for (const GltfInstance& inst : asset.instances) {
    const Mesh& m = asset.meshes[inst.mesh];
    for (size_t t = 0; t < m.TriangleCount(); ++t) {
      Eigen::Vector3d p[3];
      for (int k = 0; k < 3; ++k) p[k] = inst.file_from_mesh * m.positions[m.indices[3 * t + k]].cast<double>();
      Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]).normalized();
      const double x = p[0].x();
      for (const Slot& s : part.slots)
        if (std::abs(n.x()) > 0.999 && (std::abs(x - s.x0) < 1e-7 || std::abs(x - s.x1) < 1e-7))
          part.bottom_z = std::min({part.bottom_z, p[0].z(), p[1].z(), p[2].z()});
    }
  }
  return part;
}

struct ProfilePoint {
  int column;
  double x, z;
};

// One point per column (the first when several): columns of the scan line.
// The measured points' world positions come from the scan (centers/NNNNNN.csv),
// the truth centres' from their camera-frame points and the frame's pose.
std::vector<ProfilePoint> ReadProfile(const RunFrame& frame, const fs::path& csv, bool truth) {
  std::vector<std::pair<double, Eigen::Vector3d>> points;  // u, world point
  if (truth) {
    for (const TruthCenter& c : ReadTruthCentersCsv(csv)) points.emplace_back(c.u, *frame.world_from_cam * c.p_in_cam);
  } else {
    for (const ScanPoint& p : ReadScanCsv(csv))
      if (p.p_in_world) points.emplace_back(p.pixel.u, *p.p_in_world);
  }
  std::map<int, ProfilePoint> by_column;
  for (const auto& [u, w] : points) {
    if (!std::isfinite(w.x()) || !std::isfinite(w.z())) continue;
    int col = int(std::lround(u));
    by_column.emplace(col, ProfilePoint{col, w.x(), w.z()});
  }
  std::vector<ProfilePoint> out;
  for (auto& [c, p] : by_column) out.push_back(p);
  return out;
}

struct Gap {
  double x0, x1;
  double center() const { return 0.5 * (x0 + x1); }
};

// Gaps of a profile: runs of columns that are low (z below mid) or empty,
// bounded by top-surface columns on both sides.
std::vector<Gap> FindGaps(const std::vector<ProfilePoint>& pts, double mid_z, double top_z) {
  std::vector<Gap> gaps;
  if (pts.size() < 3) return gaps;
  // Column pitch in x (median of neighbouring differences).
  std::vector<double> dx;
  for (size_t i = 1; i < pts.size(); ++i)
    if (pts[i].column == pts[i - 1].column + 1) dx.push_back(pts[i].x - pts[i - 1].x);
  if (dx.empty()) return gaps;
  std::nth_element(dx.begin(), dx.begin() + dx.size() / 2, dx.end());
  const double pitch = dx[dx.size() / 2];
  // Top: within a quarter of the slot depth of the top surface. Points between
  // (mixed edge pixels) or above it (outliers) neither bound nor split a gap.
  const double quarter = 0.5 * (top_z - mid_z);
  auto is_top = [&](const ProfilePoint& p) { return std::abs(p.z - top_z) < quarter; };
  size_t i = 0;
  while (i < pts.size() && !is_top(pts[i])) ++i;
  while (i < pts.size()) {
    size_t j = i + 1;  // i is a top point; find the next top point
    while (j < pts.size() && !is_top(pts[j])) ++j;
    if (j >= pts.size()) break;
    // At least two columns between the top points: one stray low point on a
    // land is noise, not a slot.
    const bool gap = pts[j].column > pts[i].column + 2;
    if (gap) {
      Gap g;
      if (j > i + 1 && pts[i + 1].column == pts[i].column + 1 && pts[i + 1].z < mid_z) {
        const ProfilePoint &a = pts[i], &b = pts[i + 1];
        g.x0 = a.x + (b.x - a.x) * (a.z - mid_z) / (a.z - b.z);
      } else {
        g.x0 = pts[i].x + 0.5 * pitch;
      }
      if (j > i + 1 && pts[j - 1].column == pts[j].column - 1 && pts[j - 1].z < mid_z) {
        const ProfilePoint &a = pts[j - 1], &b = pts[j];
        g.x1 = a.x + (b.x - a.x) * (mid_z - a.z) / (b.z - a.z);
      } else {
        g.x1 = pts[j].x - 0.5 * pitch;
      }
      if (g.x1 < g.x0) std::swap(g.x0, g.x1);
      gaps.push_back(g);
    }
    i = j;
  }
  return gaps;
}

struct SlotResult {
  bool detected = false;
  double measured = NAN;  // m
};

// Measures each slot in the frame where it is nearest the image centre.
std::vector<SlotResult> MeasureRun(const fs::path& run, const PartGeometry& part, bool truth, int* false_gaps) {
  std::vector<RunFrame> frames = ReadRunManifest(run);
  std::vector<SlotResult> best(part.slots.size());
  std::vector<double> best_offset(part.slots.size(), INFINITY);
  const double mid = 0.5 * (part.top_z + part.bottom_z);
  *false_gaps = 0;
  for (const RunFrame& f : frames) {
    if (!f.IsLaserFrame() || !f.world_from_cam) continue;
    char name[32];
    std::snprintf(name, sizeof name, "%06lld", static_cast<long long>(f.index));
    fs::path csv = truth ? run / "gt" / (std::string(name) + "_centers.csv") : run / "centers" / (std::string(name) + ".csv");
    std::vector<ProfilePoint> pts = ReadProfile(f, csv, truth);
    if (pts.empty()) continue;
    std::vector<Gap> gaps = FindGaps(pts, mid, part.top_z);
    const double cam_x = f.world_from_cam->translation().x();
    const double lo = pts.front().x < pts.back().x ? pts.front().x : pts.back().x;
    const double hi = std::max(pts.front().x, pts.back().x);
    for (const Gap& g : gaps) {
      bool matched = false;
      for (const Slot& s : part.slots) matched |= g.center() >= s.x0 - 0.1e-3 && g.center() <= s.x1 + 0.1e-3;
      *false_gaps += !matched;
    }
    for (size_t k = 0; k < part.slots.size(); ++k) {
      const Slot& s = part.slots[k];
      if (s.x0 < lo || s.x1 > hi) continue;  // not fully inside this frame's profile
      double offset = std::abs(s.center() - cam_x);
      if (offset >= best_offset[k]) continue;
      best_offset[k] = offset;
      SlotResult r;
      int inside = 0;
      for (const Gap& g : gaps)
        if (g.center() >= s.x0 - 0.1e-3 && g.center() <= s.x1 + 0.1e-3) ++inside, r.measured = g.x1 - g.x0;
      r.detected = inside == 1;
      if (!r.detected) r.measured = NAN;
      best[k] = r;
    }
  }
  return best;
}

int Run(int argc, char** argv) {
  CLI::App app{"Gap resolution experiment: slot widths measured in scanned runs vs the part's geometry"};
  std::string out, glb;
  std::vector<std::string> runs;
  app.add_option("OUT_DIR", out, "Folder for gap_resolution.csv and .svg")->required();
  app.add_option("PART_GLB", glb, "The slot test part (scenes/demo/test_part.glb)")->required();
  app.add_option("RUNS", runs, "LABEL=RUN_DIR, scanned runs (lasertwin render, lasertwin scan)")->required();
  CLI11_PARSE(app, argc, argv);

  PartGeometry part = ReadPart(glb);
  fs::create_directories(out);
  std::ostringstream csv;
  csv << "label,true_width_mm,measured_width_mm,error_mm,relative_error,detected,truth_width_mm,truth_error_mm\n";
  std::vector<SvgSeries> widths, errors;
  auto dashed = [](const std::string& name) {
    SvgSeries s;
    s.name = name, s.color = "#888888", s.markers = false, s.line = true, s.dashed = true;
    return s;
  };
  SvgSeries ideal = dashed("ideal");
  for (const Slot& s : part.slots) ideal.x.push_back(s.width() * 1e3), ideal.y.push_back(s.width() * 1e3);
  widths.push_back(ideal);
  std::cout << "label   smallest detected  all detected  false gaps  max |error| >= 0.4 mm  mean |error|\n";
  for (size_t r = 0; r < runs.size(); ++r) {
    auto eq = runs[r].find('=');
    if (eq == std::string::npos) throw InputError(runs[r], "expected LABEL=RUN_DIR");
    const std::string label = runs[r].substr(0, eq);
    const fs::path dir = runs[r].substr(eq + 1);
    int false_scan = 0, false_truth = 0;
    std::vector<SlotResult> scan = MeasureRun(dir, part, false, &false_scan);
    std::vector<SlotResult> truth = MeasureRun(dir, part, true, &false_truth);
    SvgSeries w;
    w.name = label, w.color = SvgColor(int(r)), w.line = true;
    SvgSeries e = w;
    double smallest = NAN, worst_big = 0, sum_abs = 0;
    int detected = 0;
    for (size_t k = 0; k < part.slots.size(); ++k) {
      const double tw = part.slots[k].width();
      const SlotResult& s = scan[k];
      const double err = s.measured - tw;
      csv << label << "," << tw * 1e3 << "," << s.measured * 1e3 << "," << err * 1e3 << "," << err / tw << ","
          << (s.detected ? 1 : 0) << "," << truth[k].measured * 1e3 << "," << (truth[k].measured - tw) * 1e3 << "\n";
      w.x.push_back(tw * 1e3), w.y.push_back(s.measured * 1e3);
      e.x.push_back(tw * 1e3), e.y.push_back(100 * err / tw);
      if (s.detected) {
        ++detected;
        if (!(smallest <= tw)) smallest = tw;
        sum_abs += std::abs(err);
        if (tw >= 0.4e-3 - 1e-9) worst_big = std::max(worst_big, std::abs(err) / tw);
      }
    }
    std::printf("%-7s %8.2f mm %13d/%zu %11d %20.1f%% %11.3f mm\n", label.c_str(), smallest * 1e3, detected,
                part.slots.size(), false_scan, 100 * worst_big, detected ? sum_abs / detected * 1e3 : NAN);
    widths.push_back(w);
    errors.push_back(e);
  }
  WriteFileAtomically(fs::path(out) / "gap_resolution.csv", csv.str());
  SvgPlotOptions pw;
  pw.height = 420;
  pw.title = "Measured slot width vs true width";
  pw.x_label = "true width (mm)";
  pw.y_label = "measured width (mm)";
  pw.x_min = 0, pw.x_max = 1.8, pw.y_min = 0, pw.y_max = 2.0;
  WriteFileAtomically(fs::path(out) / "gap_widths.svg", SvgPlot(pw, widths));
  SvgPlotOptions pe;
  pe.height = 420;
  pe.title = "Relative error of the measured slot width";
  pe.x_label = "true width (mm)";
  pe.y_label = "error (% of the true width)";
  pe.x_min = 0, pe.x_max = 1.8;
  SvgSeries band = dashed("+-10%");
  band.x = {0, 1.8, NAN, 0, 1.8}, band.y = {10, 10, NAN, -10, -10};
  errors.push_back(band);
  WriteFileAtomically(fs::path(out) / "gap_errors.svg", SvgPlot(pe, errors));
  std::cout << "wrote " << out << "/gap_resolution.csv, gap_widths.svg, gap_errors.svg\n";
  return 0;
}

}  // namespace
}  // namespace lt

int main(int argc, char** argv) { return lt::ExperimentMain("exp_gap", lt::Run, argc, argv); }
