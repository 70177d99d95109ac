// A numeric CSV table read by column name, for the experiment programs: the
// run folder's gt/NNNNNN_centers.csv and centers/NNNNNN.csv (docs/run-folder.md,
// docs/pipeline.md). Empty fields (a stripe point without a 3D position) read
// as NaN; anything else that is not a number is an lt::InputError "file:line".
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace lt {

struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;

  // Index of the named column; throws lt::InputError naming the file when absent.
  int Column(const std::string& name) const;
  std::filesystem::path path;
};

CsvTable ReadCsvTable(const std::filesystem::path& path);

}  // namespace lt
