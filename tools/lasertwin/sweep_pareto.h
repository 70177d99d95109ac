// The Pareto plot of `lasertwin sweep` (cmd_sweep.cpp): error against run time per
// configuration, read from a sweep's rows or from its sweep.csv (--replot), and the
// SVG with the front.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace lt::cli {

// One configuration in the Pareto plot.
struct ParetoPoint {
  std::string label;
  double time_ms = 0;   // CPU per frame, render + scan
  double error_mm = 0;  // point error rms
  double detection = 0;
  bool physics_changed = false;  // max_bounces or subsurface differ from the scene: not on the front
};

// Whether a configuration's factor changes the light transport (not on the front).
bool ChangesPhysics(const std::string& factor);

// The points of a sweep.csv (--replot). Errors name the file and line.
std::vector<ParetoPoint> ReadParetoPoints(const std::filesystem::path& csv);

// Error against time, log x, with the Pareto front (see sweep_pareto.cpp).
std::string ParetoSvg(const std::vector<ParetoPoint>& points, double min_detection, const std::string& title);

}  // namespace lt::cli
