#include "render/run_folder.h"

#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"

namespace lt {

namespace {

std::string Padded(int index) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%06d", index);
  return buf;
}

}  // namespace

std::string RunFolder::FrameImageName(int index) { return "frames/" + Padded(index) + ".png"; }
std::string RunFolder::RadianceName(int index) { return "radiance/" + Padded(index) + ".exr"; }
std::string RunFolder::GroundTruthName(int index) { return "gt/" + Padded(index) + ".exr"; }
std::string RunFolder::CentersName(int index) { return "gt/" + Padded(index) + "_centers.csv"; }

std::map<int, nlohmann::json> RunFolder::ReadManifest(const std::filesystem::path& dir) {
  std::map<int, nlohmann::json> out;
  auto path = dir / "manifest.jsonl";
  std::ifstream in(path);
  if (!in) throw InputError(path.string(), "cannot open run manifest");
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::string where = path.string() + ":" + std::to_string(line_no);
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(line);
    } catch (const nlohmann::json::exception& e) {
      throw InputError(where, std::string("invalid JSON line: ") + e.what());
    }
    if (!j.is_object() || !j.contains("index") || !j["index"].is_number_integer()) {
      throw InputError(where, "manifest line has no integer \"index\"");
    }
    int index = j["index"].get<int>();
    if (!out.emplace(index, std::move(j)).second) {
      throw InputError(where, "frame " + std::to_string(index) + " appears twice");
    }
  }
  return out;
}

RunFolder::RunFolder(const std::filesystem::path& dir, const nlohmann::json& resolved_scene, bool resume)
    : dir_(dir) {
  auto scene_path = dir / "scene.json";
  bool has_run = std::filesystem::exists(scene_path) || std::filesystem::exists(dir / "manifest.jsonl");
  if (has_run && !resume) {
    throw InputError(dir.string(), "already holds a run; pass --resume to continue it or choose a new --out");
  }
  if (std::filesystem::exists(dir) && !std::filesystem::is_directory(dir)) {
    throw InputError(dir.string(), "exists and is not a folder");
  }
  if (has_run) {
    std::ifstream in(scene_path);
    nlohmann::json old;
    try {
      old = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
      throw InputError(scene_path.string(), std::string("cannot read the run's scene: ") + e.what());
    }
    if (old != resolved_scene) {
      throw InputError(scene_path.string(),
                       "the run was rendered from a different scene; --resume needs the same scene "
                       "(choose a new --out)");
    }
    if (std::filesystem::exists(dir / "manifest.jsonl")) manifest_ = ReadManifest(dir);
  }
  std::filesystem::create_directories(dir / "frames");
  if (!std::filesystem::exists(scene_path)) WriteFileAtomically(scene_path, resolved_scene.dump(2) + "\n");
}

void RunFolder::CompleteFrame(int index, const nlohmann::json& line) {
  manifest_[index] = line;
  std::ostringstream out;
  for (const auto& [i, j] : manifest_) out << j.dump() << "\n";
  WriteFileAtomically(dir_ / "manifest.jsonl", out.str());
}

}  // namespace lt
