// The "gcode" motion: the nozzle frame and the camera placed on it along a G-code
// toolpath under each orientation rule; a UR5e carrying the nozzle, whose joints
// reproduce the camera pose by forward kinematics; unreachable prints and joint
// speed violations reported with waypoint and G-code line; the resolved JSON
// reproduces the motion.
#include "scene/motion_gcode.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "scene/motion.h"
#include "test_util.h"

namespace lt {
namespace {

using test::ErrorOf;
using test::TempDir;
using test::WriteText;
using ::testing::HasSubstr;

constexpr double kMm = 1e-3;

// Moves at 20 mm/s: (10,0) -> (50,0) -> (50,40) -> (10,40), 2 s each, after a 0.5 s
// approach from (0,0,0.2).
const char* kSquare = "G1 F1200 X10 Y0 Z0.2\nG1 X50 Y0 E1\nG1 X50 Y40 E2\nG1 X10 Y40 E3\n";
double ApproachTime() { return std::hypot(10.0, 0.2) / 20.0; }

Motion ParseMotionText(const std::string& text, const TempDir& dir) {
  json::Document doc = json::Document::Parse(text, "scene.json", dir.path());
  return ParseMotion(doc.Root());
}

const GcodeMotion& AsGcode(const Motion& m) { return std::get<GcodeMotion>(m); }

TEST(GcodeMotion, NozzleFrameAndCameraAlongTheSquare) {
  TempDir dir;
  WriteText(dir / "square.gcode", kSquare);
  Motion fixed = ParseMotionText(R"({"type": "gcode", "file": "square.gcode", "orientation": "fixed",
      "world_from_gcode": {"translation_m": [1, 2, 3]}})", dir);
  EXPECT_EQ(MotionTypeName(fixed), "gcode");
  const double t1 = ApproachTime() + 1.0;  // halfway along the first side
  Pose cam = WorldFromCamAt(fixed, t1);
  EXPECT_TRUE(cam.translation().isApprox(Eigen::Vector3d(1, 2, 3) + Eigen::Vector3d(30, 0, 0.2) * kMm, 1e-12));
  // The nozzle frame: x along the heading (fixed: +x), z down, y = z x x = -y.
  EXPECT_TRUE(cam.linear().isApprox((Eigen::Matrix3d() << 1, 0, 0, 0, -1, 0, 0, 0, -1).finished(), 1e-15));
  EXPECT_TRUE(WorldFromCamAt(fixed, t1 + 2).linear().isApprox(cam.linear(), 1e-15));  // fixed never turns
  // Without a robot the tool is the nozzle: world_from_cam = world_from_tool · nozzle_from_cam.
  EXPECT_TRUE(WorldFromToolAt(fixed, t1)->isApprox(cam * AsGcode(fixed).nozzle_from_cam.inverse(), 1e-12));

  // Heading, and a camera 40 mm behind the nozzle and 60 mm above it (nozzle z points
  // down, so "above" is -z).
  Motion heading = ParseMotionText(R"({"type": "gcode", "file": "square.gcode", "orientation": "heading",
      "nozzle_from_cam": {"translation_m": [-0.04, 0, -0.06]}})", dir);
  Pose c2 = WorldFromCamAt(heading, t1 + 2);  // halfway up the second side, moving +y
  const Pose tool2 = *WorldFromToolAt(heading, t1 + 2);
  EXPECT_TRUE(tool2.translation().isApprox(Eigen::Vector3d(50, 20, 0.2) * kMm, 1e-12));  // the nozzle tip
  EXPECT_TRUE((tool2 * AsGcode(heading).nozzle_from_cam).isApprox(c2, 1e-12));
  EXPECT_TRUE(c2.translation().isApprox(Eigen::Vector3d(50, 20 - 40, 0.2 + 60) * kMm, 1e-12));
  EXPECT_TRUE((c2.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d(0, 1, 0), 1e-15));
  EXPECT_TRUE((c2.linear() * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d(1, 0, 0), 1e-15));
  EXPECT_TRUE((c2.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d(0, 0, -1), 1e-15));
  EXPECT_NEAR(c2.linear().determinant(), 1.0, 1e-15);

  // start_time_s: sequence time 0 is G-code time 2.
  Motion later = ParseMotionText(R"({"type": "gcode", "file": "square.gcode", "orientation": "heading",
      "start_time_s": 2})", dir);
  EXPECT_TRUE(WorldFromCamAt(later, t1).isApprox(AsGcode(heading).WorldFromCam(t1 + 2) *
                                                     AsGcode(heading).nozzle_from_cam.inverse(), 1e-12));
  // Clamped after the end: the last point, last heading (-x).
  Pose end = WorldFromCamAt(heading, 100);
  EXPECT_TRUE((end.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d(-1, 0, 0), 1e-15));
  EXPECT_TRUE(MotionNotes(fixed).size() == 2u);
  // The filament the beads take, beside what a slicer's "filament used" says.
  EXPECT_THAT(MotionNotes(fixed)[0], HasSubstr("1 layer (from the extrusion heights: no layer comments); filament laid "
                                               "in beads 3.000 mm, net fed 3.000 mm (retractions subtracted)"));
  EXPECT_THAT(MotionNotes(heading)[1], HasSubstr("2 instantaneous turns, the largest 90.0 deg"));
}

TEST(GcodeMotion, CasterIsTheDefaultAndTurnsSmoothly) {
  TempDir dir;
  WriteText(dir / "square.gcode", kSquare);
  Motion m = ParseMotionText(R"({"type": "gcode", "file": "square.gcode", "caster_window_mm": 8})", dir);
  const GcodeMotion& g = AsGcode(m);
  EXPECT_EQ(g.orientation.mode, OrientationMode::kCaster);
  EXPECT_NEAR(g.orientation.caster_window_m, 0.008, 1e-15);
  // 4 mm past the corner at (50, 0): half the window each side, heading 45 degrees.
  Pose cam = WorldFromCamAt(m, ApproachTime() + 2 + 0.2);
  EXPECT_TRUE((cam.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d(1, 1, 0).normalized(), 1e-12));
  EXPECT_THAT(MotionNotes(m)[1], HasSubstr("orientation caster: largest turn rate"));
}

// A UR5e beside the bed: base at the world origin turned 90 degrees, bed 0.35 m in
// front of it, a 150 mm long nozzle on the flange, the tool frame at the nozzle tip
// with the nozzle frame's axes.
// The caster window of 20 mm keeps the caster's peak turn rate at a corner, 2 v / w =
// 2 rad/s, within the wrist's 180 deg/s (10 mm would need 229 deg/s).
const char* kRobotScene = R"({"type": "gcode", "file": "square.gcode", "orientation": "%s", "caster_window_mm": 20,
    "world_from_gcode": {"translation_m": [0.3, -0.15, 0]},
    "nozzle_from_cam": {"translation_m": [-0.04, 0, -0.06], "rotation_rpy_deg": [0, -20, 0]},
    "robot": {"type": "ur5e", "world_from_base": {"rotation_rpy_deg": [0, 0, 90]},
              "flange_from_tool": {"translation_m": [0, 0, 0.15]},
              "tool_from_cam": {"translation_m": [-0.04, 0, -0.06], "rotation_rpy_deg": [0, -20, 0]},
              "initial_joints_deg": [-90, -90, 90, -90, -90, 0]%s}})";

std::string RobotScene(const std::string& orientation, const std::string& extra = "",
                       const std::string& bed = "[0.3, -0.15, 0]") {
  char buf[2048];
  std::snprintf(buf, sizeof buf, kRobotScene, orientation.c_str(), extra.c_str());
  std::string s = buf;
  s.replace(s.find("[0.3, -0.15, 0]"), 15, bed);
  return s;
}

TEST(GcodeMotion, RobotJointsReproduceTheCameraPose) {
  TempDir dir;
  WriteText(dir / "square.gcode", kSquare);
  Motion m = ParseMotionText(RobotScene("caster"), dir);
  const GcodeMotion& g = AsGcode(m);
  ASSERT_TRUE(g.robot);
  const JointPath& jp = g.robot->program->path;
  // Every 2 mm of path: 10 mm approach + 3 x 40 mm sides.
  EXPECT_GE(jp.q.size(), size_t(1 + 5 + 3 * 20));
  EXPECT_EQ(jp.speed_violations, 0u);
  const Pose cam_from_flange = (g.robot->flange_from_tool * g.robot->tool_from_cam).inverse();
  for (size_t k = 0; k < jp.q.size(); ++k) {
    Pose by_robot = g.robot->world_from_base * Ur5eForward(jp.q[k]) * cam_from_flange.inverse();
    EXPECT_LT((by_robot.matrix() - g.WorldFromCam(jp.t_s[k]).matrix()).cwiseAbs().maxCoeff(), 1e-9) << k;
    // The tool pose the manifest records is the robot's tool frame (flange · flange_from_tool).
    const Pose tool_by_robot = g.robot->world_from_base * Ur5eForward(jp.q[k]) * g.robot->flange_from_tool;
    EXPECT_LT((tool_by_robot.matrix() - WorldFromToolAt(m, jp.t_s[k])->matrix()).cwiseAbs().maxCoeff(), 1e-9) << k;
    // No branch flips: the caster turns at most 2 v / w = 2 rad/s, 0.2 rad per 2 mm step.
    if (k > 0) {
      EXPECT_LT((jp.q[k] - jp.q[k - 1]).cwiseAbs().maxCoeff(), 0.25) << k;
    }
  }
  // Between waypoints the joints interpolate linearly.
  double t = 0.5 * (jp.t_s[3] + jp.t_s[4]);
  EXPECT_TRUE(g.JointsAt(t).isApprox(0.5 * (jp.q[3] + jp.q[4]), 1e-12));
  EXPECT_THAT(MotionNotes(m)[2], HasSubstr("within the joint position and speed limits"));
}

TEST(GcodeMotion, RobotProblemsNameTheWaypointAndGcodeLine) {
  TempDir dir;
  WriteText(dir / "square.gcode", kSquare);
  // The bed 2 m away: the first waypoint is out of reach.
  EXPECT_THAT(ErrorOf([&] { ParseMotionText(RobotScene("caster", "", "[2, 0, 0]"), dir); }),
              HasSubstr("scene.json: /robot: waypoint 0 ("));
  EXPECT_THAT(ErrorOf([&] { ParseMotionText(RobotScene("caster", "", "[2, 0, 0]"), dir); }),
              HasSubstr("square.gcode:1, G-code time 0.000 s): the pose is out of the UR5e's reach"));
  // Heading mode turns 90 degrees in no time at the corners: an error on request,
  // else a note.
  std::string error = ErrorOf([&] { ParseMotionText(RobotScene("heading", R"(, "joint_speed_limits": "error")"), dir); });
  EXPECT_THAT(error, HasSubstr("square.gcode:3, G-code time"));
  EXPECT_THAT(error, HasSubstr("in no time, limit 180 deg/s (2 steps exceed a joint speed limit)"));
  Motion warned = ParseMotionText(RobotScene("heading"), dir);
  EXPECT_THAT(MotionNotes(warned)[2], HasSubstr("2 steps exceed a joint speed limit; the worst at"));
}

TEST(GcodeMotion, TurnRateLimitKeepsTheWristWithinItsSpeed) {
  TempDir dir;
  WriteText(dir / "square.gcode", kSquare);
  // Heading mode held to 90 deg/s: each 90 degree corner is a 1 s turn, not a jump.
  std::string text = RobotScene("heading");
  text.insert(text.find("\"caster_window_mm\""), "\"max_turn_deg_s\": 90, ");
  Motion m = ParseMotionText(text, dir);
  const GcodeMotion& g = AsGcode(m);
  ASSERT_TRUE(g.robot);
  const JointPath& jp = g.robot->program->path;
  EXPECT_EQ(jp.speed_violations, 0u);
  const Pose cam_from_flange = (g.robot->flange_from_tool * g.robot->tool_from_cam).inverse();
  for (size_t k = 0; k < jp.q.size(); ++k) {
    Pose by_robot = g.robot->world_from_base * Ur5eForward(jp.q[k]) * cam_from_flange.inverse();
    EXPECT_LT((by_robot.matrix() - g.WorldFromCam(jp.t_s[k]).matrix()).cwiseAbs().maxCoeff(), 1e-9) << k;
    if (k > 0) {
      EXPECT_GT(jp.t_s[k], jp.t_s[k - 1]) << k;  // no two waypoints at one time: no jump
    }
  }
  const std::vector<std::string> notes = MotionNotes(m);
  EXPECT_THAT(notes[1], HasSubstr("largest turn rate 90.0 deg/s"));
  EXPECT_THAT(notes[1], HasSubstr("held to 90.0 deg/s: 2 turns at that rate behind the rule's, the longest 1.0"));
  EXPECT_THAT(notes[2], HasSubstr("within the joint position and speed limits"));
  // Halfway round the first corner (G-code time: approach + 2 s + 0.5 s), 45 degrees.
  // The nozzle frame's x is the heading; the turn starts at most one 1 ms step late.
  auto heading_x = [&](double t) { return Eigen::Vector3d((g.WorldFromCam(t) * g.nozzle_from_cam.inverse()).linear().col(0)); };
  EXPECT_NEAR(std::acos(heading_x(ApproachTime() + 2.5).dot(heading_x(ApproachTime() + 1.0))), M_PI / 4,
              M_PI / 2 * 1e-3 + 1e-9);
  EXPECT_EQ(MotionToJson(m)["max_turn_deg_s"], 90.0);
  EXPECT_FALSE(MotionToJson(ParseMotionText(RobotScene("heading"), dir)).contains("max_turn_deg_s"));
}

TEST(GcodeMotion, WindingLimitUnwindsTheWristBeforeItsRange) {
  // Three laps of a circle turn the scanner through 1080 degrees: wrist 3 (+-360) cannot
  // follow, and the arm would flip its configuration. Bounded to 300 degrees of winding
  // the scanner unwinds a whole turn at 90 deg/s each time it gets there.
  TempDir dir;
  WriteText(dir / "laps.gcode", "G1 F1200 X50 Y20 Z0.2\nG3 X50 Y20 I-20 J0 E1\nG3 X50 Y20 I-20 J0 E2\n"
                                "G3 X50 Y20 I-20 J0 E3\n");
  auto scene = [&](const std::string& limits) {
    std::string text = RobotScene("heading");
    text.replace(text.find("square.gcode"), 12, "laps.gcode");
    text.insert(text.find("\"caster_window_mm\""), limits);
    return text;
  };
  Motion wound = ParseMotionText(scene(R"("max_turn_deg_s": 90, )"), dir);
  ASSERT_TRUE(AsGcode(wound).robot);
  EXPECT_GT(AsGcode(wound).robot->program->path.speed_violations, 0u);
  EXPECT_THAT(MotionNotes(wound)[2], HasSubstr("the arm changes configuration: wrist 3 would reach"));

  Motion m = ParseMotionText(scene(R"("max_turn_deg_s": 90, "max_winding_deg": 300, )"), dir);
  const GcodeMotion& g = AsGcode(m);
  ASSERT_TRUE(g.robot);
  const JointPath& jp = g.robot->program->path;
  EXPECT_EQ(jp.speed_violations, 0u);
  for (const JointVector& q : jp.q) EXPECT_LE(q.cwiseAbs().maxCoeff(), 2 * M_PI);
  const TurnRates r = g.toolpath->ComputeTurnRates();
  EXPECT_GE(r.unwinds, 2u);  // 1080 - 300 degrees to shed, a turn at a time
  EXPECT_LE(r.max_winding_rad, 300 * M_PI / 180 + 1e-9);
  EXPECT_THAT(MotionNotes(m)[1], HasSubstr("deg from the start (limit 300.0), " + std::to_string(r.unwinds) + " unwinds"));
  EXPECT_THAT(MotionNotes(m)[2], HasSubstr("within the joint position and speed limits"));
  EXPECT_EQ(MotionToJson(m)["max_winding_deg"], 300.0);
}

TEST(GcodeMotion, ResolvedJsonReproducesTheMotion) {
  TempDir dir;
  WriteText(dir / "square.gcode", kSquare);
  Motion m = ParseMotionText(RobotScene("caster", R"(, "check_step_mm": 5)"), dir);
  nlohmann::json j = MotionToJson(m);
  EXPECT_EQ(j["file"], (dir.path() / "square.gcode").lexically_normal().string());
  EXPECT_EQ(j["orientation"], "caster");
  EXPECT_EQ(j["caster_window_mm"], 20.0);
  EXPECT_EQ(j["robot"]["check_step_mm"], 5.0);
  EXPECT_EQ(j["robot"]["joint_speed_limits"], "warn");
  TempDir elsewhere;
  Motion again = ParseMotionText(j.dump(), elsewhere);
  for (double t : {0.0, 0.3, 1.7, 4.2, 6.0}) {
    EXPECT_TRUE(WorldFromCamAt(again, t).isApprox(WorldFromCamAt(m, t), 1e-12)) << t;
  }
  EXPECT_EQ(AsGcode(again).robot->program->path.q.size(), AsGcode(m).robot->program->path.q.size());
}

TEST(GcodeMotion, SceneErrors) {
  TempDir dir;
  WriteText(dir / "square.gcode", kSquare);
  WriteText(dir / "empty.gcode", "M104 S200\n; nothing moves\n");
  WriteText(dir / "bad.gcode", "G1 F600 X1\nG1 Xq\n");
  auto error = [&](const std::string& text) { return ErrorOf([&] { ParseMotionText(text, dir); }); };
  EXPECT_THAT(error(R"({"type": "gcode", "file": "square.gcode", "orientation": "spin"})"), HasSubstr("/orientation"));
  EXPECT_THAT(error(R"({"type": "gcode", "file": "square.gcode", "caster_window_mm": 0})"),
              HasSubstr("/caster_window_mm: must be > 0"));
  EXPECT_THAT(error(R"({"type": "gcode", "file": "square.gcode", "start_time_s": -1})"), HasSubstr("/start_time_s"));
  EXPECT_THAT(error(R"({"type": "gcode", "file": "square.gcode", "max_turn_deg_s": 0})"),
              HasSubstr("/max_turn_deg_s: must be > 0"));
  EXPECT_THAT(error(R"({"type": "gcode", "file": "square.gcode", "max_winding_deg": 300})"),
              HasSubstr("/max_winding_deg: needs max_turn_deg_s, the rate to unwind at"));
  EXPECT_THAT(error(R"({"type": "gcode", "file": "square.gcode", "max_turn_deg_s": 90, "max_winding_deg": 100})"),
              HasSubstr("/max_winding_deg"));
  EXPECT_THAT(error(R"({"type": "gcode", "file": "empty.gcode"})"), HasSubstr("/file: the G-code file has no moves"));
  EXPECT_THAT(error(R"({"type": "gcode", "file": "bad.gcode"})"), HasSubstr("bad.gcode:2: X without a number"));
  EXPECT_THAT(error(R"({"type": "gcode", "file": "missing.gcode"})"),
              HasSubstr("/file: G-code file not found (looked for " + (dir / "missing.gcode").string() + ")"));
  EXPECT_THAT(error(R"({"type": "gcode", "file": "square.gcode", "robot": {"type": "ur10"}})"), HasSubstr("/robot/type"));
  EXPECT_THAT(error(R"({"type": "gcode", "file": "square.gcode", "robot": {"type": "ur5e", "reach": 1}})"),
              HasSubstr("reach"));
  EXPECT_THAT(error(R"({"type": "gcode", "file": "square.gcode", "robot": {"type": "ur5e",
      "initial_joints_deg": [0, 0, 0]}})"), HasSubstr("/robot/initial_joints_deg"));
  EXPECT_THAT(error(R"({"type": "gcode", "file": "square.gcode", "speed": 2})"), HasSubstr("speed"));
}

}  // namespace
}  // namespace lt
