// The small rendered calibration session the calibrate command-line tests
// share (rendered once per test program), and that session recorded as a real
// capture (frames only, and a robot pose log).
#pragma once

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "run_many.h"

namespace lt::test {

inline const std::filesystem::path kSource = LT_SOURCE_DIR;

// The rendered session, shared by the tests (rendered once).
struct Session {
  std::filesystem::path dir, run;
  bool ok = false;
};

inline const Session& RenderedSession() {
  static Session s;
  static std::once_flag once;
  std::call_once(once, [] {
    s.dir = NewTestFolder("calibrate_session");
    s.run = s.dir / "run";
    const CliResult gen = RunCli("calib-session --out " + Quoted(s.dir / "session") + " --rig " +
                                 Quoted(kSource / "scenes/demo/scene.json") +
                                 " --arm --views 6 --binning 4 --spp 2 --quiet");
    EXPECT_EQ(gen.exit_code, 0) << gen.err;
    const CliResult render =
        RunCli("render " + Quoted(s.dir / "session/scene.json") + " --out " + Quoted(s.run) + " --quiet");
    EXPECT_EQ(render.exit_code, 0) << render.err;
    s.ok = gen.exit_code == 0 && render.exit_code == 0;
  });
  return s;
}

// The session's frames as a real capture records them: frames/ only (no
// manifest.jsonl, rig.json or scene.json), and the robot's log of the tool
// poses beside it, one per frame, in mm with a header (from the manifest's
// world_from_tool); `every` keeps every every-th pose (2: one per bright frame),
// `count` at most that many.
inline std::filesystem::path CaptureOfSession(const std::string& name, std::filesystem::path* poses, size_t every = 1, size_t count = 1000) {
  const Session& s = RenderedSession();
  const std::filesystem::path dir = NewTestFolder(name);
  std::filesystem::create_directories(dir / "capture/frames");
  std::filesystem::copy(s.run / "frames", dir / "capture/frames", std::filesystem::copy_options::recursive);
  *poses = dir / "robot_poses.csv";
  std::ofstream out(*poses);
  out << "x_mm,y_mm,z_mm,qw,qx,qy,qz\n";
  std::stringstream in(ReadFile(s.run / "manifest.jsonl"));
  std::string line;
  for (size_t i = 0; std::getline(in, line) && i < every * count; ++i) {
    if (i % every != 0) continue;
    const nlohmann::json tool = nlohmann::json::parse(line).at("world_from_tool");
    char row[256];
    const auto& t = tool.at("translation_m");
    const auto& q = tool.at("rotation_quat_wxyz");
    std::snprintf(row, sizeof row, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", 1e3 * double(t[0]),
                  1e3 * double(t[1]), 1e3 * double(t[2]), double(q[0]), double(q[1]), double(q[2]), double(q[3]));
    out << row;
  }
  return dir / "capture";
}

}  // namespace lt::test
