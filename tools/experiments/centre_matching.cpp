#include "centre_matching.h"

#include <cmath>
#include <map>

#include "csv_table.h"

namespace lt {

std::vector<FrameCentre> ReadFrameCentres(const std::filesystem::path& csv, bool column_lines) {
  CsvTable t = ReadCsvTable(csv);
  const int cu = t.Column("u"), cv = t.Column("v"), cp = t.Column("plane");
  int cx = -1;
  for (size_t i = 0; i < t.header.size(); ++i)
    if (t.header[i] == "x_world") cx = int(i);
  std::vector<FrameCentre> out;
  for (const auto& r : t.rows) {
    FrameCentre c;
    const double u = r[size_t(cu)], v = r[size_t(cv)];
    c.line = int(std::lround(column_lines ? u : v));
    c.pos = column_lines ? v : u;
    c.plane = std::isfinite(r[size_t(cp)]) ? int(r[size_t(cp)]) : -1;
    if (cx >= 0) c.p_world = Eigen::Vector3d(r[size_t(cx)], r[size_t(cx) + 1], r[size_t(cx) + 2]);
    out.push_back(c);
  }
  return out;
}

std::vector<int> MatchToTruth(const std::vector<FrameCentre>& measured, const std::vector<FrameCentre>& truth,
                              double max_distance_px) {
  std::multimap<int, int> by_line;
  for (size_t i = 0; i < truth.size(); ++i) by_line.emplace(truth[i].line, int(i));
  std::vector<int> match(measured.size(), -1);
  for (size_t k = 0; k < measured.size(); ++k) {
    double best = max_distance_px;
    auto [lo, hi] = by_line.equal_range(measured[k].line);
    for (auto it = lo; it != hi; ++it) {
      double d = std::abs(measured[k].pos - truth[size_t(it->second)].pos);
      if (d <= best) best = d, match[k] = it->second;
    }
  }
  return match;
}

}  // namespace lt
