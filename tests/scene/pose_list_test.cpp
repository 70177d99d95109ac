// Pose lists: both file formats, interpolation against closed forms (linear
// position, constant-rate rotation along the shorter arc), clamping, the motion
// type in a scene file, and every kind of bad file reported at file:line.
#include "scene/pose_list.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "scene/motion.h"
#include "test_util.h"

namespace lt {
namespace {

namespace fs = std::filesystem;
using test::ErrorOf;
using ::testing::HasSubstr;

const fs::path kPoses = fs::path(LT_SOURCE_DIR) / "tests/data/poses";

double AngleAboutZ(const Pose& p) {
  Eigen::Vector3d x = p.linear() * Eigen::Vector3d::UnitX();
  return std::atan2(x.y(), x.x());
}

// Rotation angle between two poses' rotations (radians).
double RotationDistance(const Pose& a, const Pose& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

TEST(PoseList, CsvInterpolatesLinearlyAndSlerps) {
  PoseTrajectory traj = ReadPoseList(kPoses / "sweep.csv", PoseFileFormat::kCsv);
  ASSERT_EQ(traj.samples().size(), 3u);
  // Constant velocity 0.1 m/s along x and 45 deg/s about z: every time in between
  // is a closed form, also inside the intervals.
  for (double t : {0.0, 0.25, 0.5, 1.0, 1.3, 1.75, 2.0}) {
    Pose p = traj.At(t);
    EXPECT_NEAR(p.translation().x(), 0.1 * t, 1e-15) << t;
    EXPECT_NEAR(p.translation().z(), 0.3, 1e-15);
    EXPECT_NEAR(AngleAboutZ(p), M_PI / 4 * t, 1e-12) << t;
    EXPECT_NEAR(p.linear().determinant(), 1.0, 1e-12);
  }
}

TEST(PoseList, ClampedBeforeTheFirstAndAfterTheLastPose) {
  PoseTrajectory traj = ReadPoseList(kPoses / "sweep.csv", PoseFileFormat::kCsv);
  EXPECT_TRUE(traj.At(-3.0).isApprox(traj.At(0.0), 1e-15));
  EXPECT_TRUE(traj.At(7.0).isApprox(traj.At(2.0), 1e-15));
  EXPECT_NEAR(traj.At(7.0).translation().x(), 0.2, 1e-15);
  EXPECT_TRUE(traj.At(std::nan("")).isApprox(traj.At(0.0), 1e-15));  // never garbage
}

TEST(PoseList, TumHasTheQuaternionWLastAndTheSameTrajectory) {
  PoseTrajectory csv = ReadPoseList(kPoses / "sweep.csv", PoseFileFormat::kCsv);
  PoseTrajectory tum = ReadPoseList(kPoses / "sweep.tum", PoseFileFormat::kTum);
  EXPECT_DOUBLE_EQ(tum.StartTime(), 1305031102.0);
  // A Unix time stamp near 1.3e9 s holds time to 2.4e-7 s (its double spacing), so
  // positions agree to about 0.1 m/s * 2.4e-7 s and rotations to 1e-6 rad.
  for (double u : {0.0, 0.4, 1.0, 1.6, 2.0}) {
    EXPECT_TRUE(tum.At(tum.StartTime() + u).isApprox(csv.At(u), 1e-6)) << u;
  }
}

TEST(PoseList, SlerpTakesTheShorterArcWhateverTheQuaternionSign) {
  // 170 degrees about z written once as q and once as -q: both halfway poses are
  // 85 degrees, never the long way round (-95 degrees).
  double half = 170.0 / 2 * M_PI / 180;
  for (double sign : {1.0, -1.0}) {
    std::vector<PoseSample> s(2);
    s[1].t_s = 1;
    s[1].rotation = Eigen::Quaterniond(sign * std::cos(half), 0, 0, sign * std::sin(half));
    PoseTrajectory traj(s);
    EXPECT_NEAR(AngleAboutZ(traj.At(0.5)), 85 * M_PI / 180, 1e-12) << sign;
  }
}

TEST(PoseList, RotationRateIsConstantBetweenTwoPoses) {
  // Slerp about a general axis: the angle from the first pose grows linearly.
  Eigen::Quaterniond q1(Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, 2, 3).normalized()));
  std::vector<PoseSample> s(2);
  s[0].t_s = 10;
  s[1].t_s = 14;
  s[1].rotation = q1;
  PoseTrajectory traj(s);
  for (double u : {0.1, 0.3, 0.5, 0.9}) {
    EXPECT_NEAR(RotationDistance(traj.At(10), traj.At(10 + 4 * u)), 2.0 * u, 1e-12) << u;
  }
}

struct BadCase {
  const char* name;
  PoseFileFormat format;
  const char* text;
  const char* expected;
};

TEST(PoseList, BadFilesNameTheFileAndLine) {
  const char* header = "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n";
  const std::vector<BadCase> cases = {
      {"bad number", PoseFileFormat::kCsv, "0,0,0,0,1,0,0,0\n1,0,abc,0,1,0,0,0\n", "p.csv:3: field 3 is not a finite number: \"abc\""},
      {"nan", PoseFileFormat::kCsv, "0,0,0,0,1,0,0,0\n1,nan,0,0,1,0,0,0\n", "p.csv:3: field 2 is not a finite number: \"nan\""},
      {"empty field", PoseFileFormat::kCsv, "0,0,0,0,1,0,0,0\n1,,0,0,1,0,0,0\n", "p.csv:3: field 2 is not a finite number"},
      {"field count", PoseFileFormat::kCsv, "0,0,0,0,1,0,0\n", "p.csv:2: expected 8 fields"},
      {"same time", PoseFileFormat::kCsv, "0,0,0,0,1,0,0,0\n\n0,1,0,0,1,0,0,0\n", "p.csv:4: time 0 does not increase"},
      {"time back", PoseFileFormat::kCsv, "1,0,0,0,1,0,0,0\n0.5,1,0,0,1,0,0,0\n", "p.csv:3: time 0.5 does not increase"},
      {"not unit", PoseFileFormat::kCsv, "0,0,0,0,1,0,0,0\n1,0,0,0,1,0,0,0.1\n", "p.csv:3: quaternion must have unit norm"},
      {"one pose", PoseFileFormat::kCsv, "0,0,0,0,1,0,0,0\n", "p.csv: a pose list needs at least two poses, got 1"},
  };
  for (const auto& c : cases) {
    EXPECT_THAT(ErrorOf([&] { ParsePoseList(std::string(header) + c.text, c.format, "p.csv"); }), HasSubstr(c.expected))
        << c.name;
  }
  EXPECT_THAT(ErrorOf([&] { ParsePoseList("t,x,y,z,qw,qx,qy,qz\n", PoseFileFormat::kCsv, "p.csv"); }),
              HasSubstr("p.csv:1: expected the header"));
  EXPECT_THAT(ErrorOf([&] { ParsePoseList("", PoseFileFormat::kCsv, "p.csv"); }), HasSubstr("p.csv: empty pose list"));
  EXPECT_THAT(ErrorOf([&] { ParsePoseList("# only\n0 0 0 0 0 0 0 1\n", PoseFileFormat::kTum, "p.tum"); }),
              HasSubstr("p.tum: a pose list needs at least two poses"));
  EXPECT_THAT(ErrorOf([&] { ParsePoseList("0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1 9\n", PoseFileFormat::kTum, "p.tum"); }),
              HasSubstr("p.tum:2: expected 8 fields (timestamp tx ty tz qx qy qz qw), got 9"));
  // TUM puts w last: "1 0 0 0" read as xyzw is not the identity but a 180-degree turn;
  // "0 0 0 2" is not unit.
  EXPECT_THAT(ErrorOf([&] { ParsePoseList("0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 2\n", PoseFileFormat::kTum, "p.tum"); }),
              HasSubstr("p.tum:2: quaternion must have unit norm (to 1e-3), got norm 2"));
  EXPECT_THAT(ErrorOf([&] { ReadPoseList(kPoses / "missing.csv", PoseFileFormat::kCsv, "missing.csv"); }),
              HasSubstr("missing.csv: cannot open file"));
}

// A TUM trajectory read with the default "format" (csv), a CSV file given "tum", and
// CSV poses without their header were refused with the bare "expected the header"
// or "expected 8 fields", which did not say that "format" was what to change.
TEST(PoseList, AFileOfTheOtherFormatSaysWhatToChange) {
  EXPECT_EQ(ErrorOf([&] { ParsePoseList("# TUM\n1700000000.0 0 0 0.1 0 0 0 1\n", PoseFileFormat::kCsv, "p.txt"); }),
            "p.txt:2: expected the header \"t_s,x_m,y_m,z_m,qw,qx,qy,qz\", got \"1700000000.0 0 0 0.1 0 0 0 1\" (8 "
            "numbers separated by blanks: a TUM trajectory? give the motion \"format\": \"tum\")");
  EXPECT_THAT(ErrorOf([&] { ParsePoseList("0,0,0,0.1,1,0,0,0\n1,0,0,0.1,1,0,0,0\n", PoseFileFormat::kCsv, "p.csv"); }),
              ::testing::EndsWith("(a pose before the header: the header comes first)"));
  EXPECT_THAT(ErrorOf([&] { ParsePoseList("t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n", PoseFileFormat::kTum, "p.csv"); }),
              ::testing::EndsWith("got 1 (fields separated by commas: a CSV pose list? leave out the motion's "
                                  "\"format\": \"tum\")"));
  // Other bad lines get no hint.
  EXPECT_THAT(ErrorOf([&] { ParsePoseList("t,x,y,z,qw,qx,qy,qz\n", PoseFileFormat::kCsv, "p.csv"); }),
              ::testing::EndsWith("got \"t,x,y,z,qw,qx,qy,qz\""));
  EXPECT_THAT(ErrorOf([&] { ParsePoseList("t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0 0 0 0 1 0 0 0\n", PoseFileFormat::kCsv, "p.csv"); }),
              ::testing::EndsWith("got 1"));
}

TEST(PoseList, CrlfAndCommentsAreAccepted) {
  PoseTrajectory traj = ParsePoseList(
      "t_s,x_m,y_m,z_m,qw,qx,qy,qz\r\n# comment\r\n0, 0,0,0, 1,0,0,0\r\n\r\n2,+1.,0,0,1,0,0,0\r\n", PoseFileFormat::kCsv,
      "p.csv");
  EXPECT_NEAR(traj.At(1).translation().x(), 0.5, 1e-15);
}

// Excel's "CSV UTF-8" and Windows editors start the file with a byte order mark;
// it was read as part of the header ("expected the header ..."), or of a TUM time.
TEST(PoseList, AByteOrderMarkIsSkipped) {
  const std::string bom = "\xEF\xBB\xBF";
  PoseTrajectory csv = ParsePoseList(bom + "t_s,x_m,y_m,z_m,qw,qx,qy,qz\r\n0,0,0,0,1,0,0,0\r\n2,1,0,0,1,0,0,0\r\n",
                                     PoseFileFormat::kCsv, "p.csv");
  EXPECT_NEAR(csv.At(1).translation().x(), 0.5, 1e-15);
  PoseTrajectory tum = ParsePoseList(bom + "0 0 0 0 0 0 0 1\n2 1 0 0 0 0 0 1\n", PoseFileFormat::kTum, "p.tum");
  EXPECT_NEAR(tum.At(1).translation().x(), 0.5, 1e-15);
  // Only at the start of the file: elsewhere the bytes are no number.
  EXPECT_THAT(ErrorOf([&] { ParsePoseList("0 0 0 0 0 0 0 1\n" + bom + "2 1 0 0 0 0 0 1\n", PoseFileFormat::kTum, "p.tum"); }),
              HasSubstr("p.tum:2: field 1 is not a finite number"));
}

// The motion section of a scene file.
Motion ParseMotionText(const std::string& text, const fs::path& base) {
  json::Document doc = json::Document::Parse(text, "scene.json", base);
  return ParseMotion(doc.Root());
}

TEST(PoseListMotion, SceneKeysTimeOriginAndHandEye) {
  Motion m = ParseMotionText(R"({"type": "pose_list", "file": "sweep.tum", "format": "tum"})", kPoses);
  EXPECT_EQ(MotionTypeName(m), "pose_list");
  // time_origin first_pose (default): sequence time 0 is the first time stamp.
  EXPECT_NEAR(WorldFromCamAt(m, 1.0).translation().x(), 0.1, 1e-9);
  nlohmann::json j = MotionToJson(m);
  EXPECT_EQ(j["file"], (kPoses / "sweep.tum").lexically_normal().string());
  EXPECT_EQ(j["format"], "tum");
  EXPECT_EQ(j["time_origin"], "first_pose");

  // time_origin file: the CSV's own times, clamped before 0.
  Motion f = ParseMotionText(
      R"({"type": "pose_list", "file": "sweep.csv", "time_origin": "file",
          "tool_from_cam": {"translation_m": [0, 0, 0.05]}})",
      kPoses);
  // The file holds world_from_tool; the camera sits 5 cm along the tool's z.
  Pose world_from_cam = WorldFromCamAt(f, 2.0);
  EXPECT_TRUE(world_from_cam.translation().isApprox(Eigen::Vector3d(0.2, 0, 0.35), 1e-12));
  EXPECT_NEAR(AngleAboutZ(world_from_cam), M_PI / 2, 1e-12);
  EXPECT_TRUE(MotionToJson(f).contains("tool_from_cam"));
}

TEST(PoseListMotion, SceneErrorsNameTheKeyOrTheFile) {
  EXPECT_THAT(ErrorOf([&] { ParseMotionText(R"({"type": "pose_list"})", kPoses); }),
              HasSubstr("\"file\""));
  EXPECT_THAT(ErrorOf([&] { ParseMotionText(R"({"type": "pose_list", "file": "sweep.csv", "format": "xyz"})", kPoses); }),
              HasSubstr("/format"));
  EXPECT_THAT(ErrorOf([&] { ParseMotionText(R"({"type": "pose_list", "file": "sweep.csv", "speed": 1})", kPoses); }),
              HasSubstr("speed"));
  // A TUM file read as CSV fails on its first data line (no header).
  EXPECT_THAT(ErrorOf([&] { ParseMotionText(R"({"type": "pose_list", "file": "sweep.tum"})", kPoses); }),
              HasSubstr("sweep.tum:2: expected the header"));
}

// Poses written in the scene itself (a linear stage's sweep needs two): the same
// trajectory as sweep.csv's, in any pose form, with the file's time origins and
// hand-eye pose; the resolved scene.json writes them back.
TEST(PoseListMotion, InlinePosesAreTheFilesTrajectory) {
  const std::string inline_poses = R"([
      {"t_s": 0, "world_from_cam": {"translation_m": [0, 0, 0.3]}},
      {"t_s": 1, "world_from_cam": {"translation_m": [0.1, 0, 0.3], "rotation_rpy_deg": [0, 0, 45]}},
      {"t_s": 2, "world_from_cam": {"translation_m": [0.2, 0, 0.3], "rotation_quat_wxyz": [0.7071067811865476, 0, 0, 0.7071067811865476]}}])";
  Motion from_file = ParseMotionText(R"({"type": "pose_list", "file": "sweep.csv"})", kPoses);
  Motion inline_motion = ParseMotionText(R"({"type": "pose_list", "poses": )" + inline_poses + "}", kPoses);
  Motion written_back = ParseMotion(
      json::Document::Parse(MotionToJson(inline_motion).dump(), "resolved.json", kPoses).Root());
  for (double t : {-1.0, 0.0, 0.4, 1.0, 1.7, 2.0, 3.0}) {
    const Pose want = WorldFromCamAt(from_file, t);
    for (const Motion* m : {&inline_motion, &written_back}) {
      const Pose got = WorldFromCamAt(*m, t);
      EXPECT_LT((got.translation() - want.translation()).norm(), 1e-15) << t;
      EXPECT_LT(RotationDistance(got, want), 1e-12) << t;
    }
  }
  EXPECT_FALSE(MotionToJson(inline_motion).contains("file"));
  EXPECT_FALSE(WorldFromToolAt(inline_motion, 0.5).has_value());

  // World_from_tool poses with the hand-eye pose, times as written.
  Motion tool = ParseMotionText(R"({"type": "pose_list", "time_origin": "file", "tool_from_cam": {"translation_m": [0, 0, 0.05]},
      "poses": [{"t_s": 1, "world_from_tool": {"translation_m": [0, 0, 0]}},
                {"t_s": 3, "world_from_tool": {"translation_m": [0.2, 0, 0]}}]})",
                                kPoses);
  EXPECT_TRUE(WorldFromCamAt(tool, 2.0).translation().isApprox(Eigen::Vector3d(0.1, 0, 0.05), 1e-15));
  EXPECT_TRUE(WorldFromToolAt(tool, 0.0)->translation().isApprox(Eigen::Vector3d(0, 0, 0), 1e-15));
  EXPECT_TRUE(MotionToJson(tool)["poses"][1].contains("world_from_tool"));
}

TEST(PoseListMotion, InlinePoseErrorsNameTheKey) {
  const std::string two = R"([{"t_s": 0, "world_from_cam": {}}, {"t_s": 1, "world_from_cam": {}}])";
  auto error = [&](const std::string& motion) { return ErrorOf([&] { ParseMotionText(motion, kPoses); }); };
  EXPECT_THAT(error(R"({"type": "pose_list", "file": "sweep.csv", "poses": )" + two + "}"),
              HasSubstr("scene.json: /poses: give either \"file\" or \"poses\", not both"));
  EXPECT_THAT(error(R"({"type": "pose_list", "format": "tum", "poses": )" + two + "}"),
              HasSubstr("scene.json: /format: applies to a pose list \"file\""));
  EXPECT_THAT(error(R"({"type": "pose_list", "poses": [{"t_s": 0, "world_from_cam": {}}]})"), HasSubstr("scene.json: /poses"));
  EXPECT_THAT(error(R"({"type": "pose_list", "poses": [{"t_s": 1, "world_from_cam": {}}, {"t_s": 1, "world_from_cam": {}}]})"),
              HasSubstr("scene.json: /poses/1/t_s: times must strictly increase, got 1 after 1"));
  EXPECT_THAT(error(R"({"type": "pose_list", "tool_from_cam": {}, "poses": )" + two + "}"),
              HasSubstr("scene.json: /poses/0/world_from_cam: with \"tool_from_cam\" the poses are the tool's"));
  EXPECT_THAT(error(R"({"type": "pose_list", "poses": [{"t_s": 0, "world_from_tool": {}}, {"t_s": 1, "world_from_cam": {}}]})"),
              HasSubstr("scene.json: /poses/0/world_from_tool: \"world_from_tool\" poses need the hand-eye pose"));
  EXPECT_THAT(error(R"({"type": "pose_list", "poses": [{"t_s": 0, "world_from_cam": {}}, {"t_s": 1, "world_from_cam": {}, "speed": 2}]})"),
              HasSubstr("scene.json: /poses/1/speed: unknown key \"speed\""));
  EXPECT_THAT(error(R"({"type": "pose_list"})"), HasSubstr("\"poses\" (the poses inline)"));
}

}  // namespace
}  // namespace lt
