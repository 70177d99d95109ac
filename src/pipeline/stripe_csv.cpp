#include "pipeline/stripe_csv.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/text_fields.h"

namespace lt {

std::string FormatStripeCsv(const std::vector<StripePoint>& points, bool with_plane) {
  std::string out = with_plane ? "u,v,width,strength,plane\n" : "u,v,width,strength\n";
  out.reserve(out.size() + points.size() * 40);
  char buf[160];
  for (const auto& p : points) {
    int len = with_plane ? std::snprintf(buf, sizeof buf, "%.4f,%.4f,%.3f,%.6g,%d\n", p.u, p.v, p.width, p.strength, p.plane)
                         : std::snprintf(buf, sizeof buf, "%.4f,%.4f,%.3f,%.6g\n", p.u, p.v, p.width, p.strength);
    out.append(buf, size_t(len));
  }
  return out;
}

void WriteStripeCsv(const std::filesystem::path& path, const std::vector<StripePoint>& points, bool with_plane) {
  WriteFileAtomically(path, FormatStripeCsv(points, with_plane));
}

std::vector<StripePoint> ReadStripeCsv(const std::filesystem::path& path, bool* with_plane) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string(), "cannot open");
  std::string line;
  if (!std::getline(in, line)) throw InputError(path.string() + ":1", "empty file, expected a CSV header");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  bool plane;
  if (line == "u,v,width,strength") {
    plane = false;
  } else if (line == "u,v,width,strength,plane") {
    plane = true;
  } else {
    throw InputError(path.string() + ":1", "expected header u,v,width,strength[,plane], got '" + line + "'");
  }
  if (with_plane) *with_plane = plane;
  std::vector<StripePoint> points;
  int number = 1;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::string where = path.string() + ":" + std::to_string(number);
    const std::vector<std::string_view> fields = SplitFields(line, ',');
    if (fields.size() != (plane ? 5u : 4u)) {
      throw InputError(where, "expected " + std::string(plane ? "5" : "4") + " fields, got " + std::to_string(fields.size()));
    }
    double v[4];
    for (size_t k = 0; k < 4; ++k) v[k] = FiniteField(fields, k, where);
    StripePoint p{v[0], v[1], v[2], v[3], -1};
    if (plane) {
      const std::optional<double> n = ParseFiniteNumber(fields[4]);
      if (!n || *n != std::floor(*n) || *n < -1 || *n > 1e6) {
        throw InputError(where, "plane must be an integer >= -1, got '" + std::string(fields[4]) + "'");
      }
      p.plane = int(*n);
    }
    points.push_back(p);
  }
  return points;
}

}  // namespace lt
