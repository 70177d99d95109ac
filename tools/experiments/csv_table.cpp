#include "csv_table.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace lt {

namespace {

std::vector<std::string> SplitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

}  // namespace

int CsvTable::Column(const std::string& name) const {
  for (size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return int(i);
  throw InputError(path.string(), "no column '" + name + "'");
}

CsvTable ReadCsvTable(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string(), "cannot open file");
  CsvTable t;
  t.path = path;
  std::string line;
  if (!std::getline(in, line)) throw InputError(path.string(), "empty file (no header)");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  t.header = SplitFields(line);
  int line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::vector<std::string> fields = SplitFields(line);
    const std::string where = path.string() + ":" + std::to_string(line_no);
    if (fields.size() != t.header.size()) {
      throw InputError(where, std::to_string(fields.size()) + " fields, the header has " +
                                  std::to_string(t.header.size()));
    }
    std::vector<double> row;
    for (const std::string& f : fields) {
      if (f.empty()) {
        row.push_back(NAN);
        continue;
      }
      size_t used = 0;
      double v = 0;
      try {
        v = std::stod(f, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != f.size() || !std::isfinite(v)) throw InputError(where, "not a finite number: '" + f + "'");
      row.push_back(v);
    }
    t.rows.push_back(std::move(row));
  }
  return t;
}

}  // namespace lt
