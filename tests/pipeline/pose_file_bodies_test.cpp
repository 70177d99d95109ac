// Pose files of several bodies (--pose-body, PoseFileOptions::body): an OptiTrack Motive
// export of three rigid bodies and a ROS tf CSV whose rows interleave two child frames.
// The chosen body's poses read exactly; without the option, or with a name the file
// does not hold, an error naming the file, the line and every body.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/error.h"
#include "pipeline/pose_file.h"
#include "pose_file_test_util.h"

namespace lt {
namespace {

using ::testing::HasSubstr;
using namespace pose_file_test;

// Body b's pose at frame k: TestPose(k) for the scanner (b = 1), others elsewhere.
Pose BodyPose(int b, int k) { return TestPose(k + 3 * (b == 1 ? 0 : b + 1)); }

// A Motive 1.23 export of the rigid bodies Robot, Scanner and Part, two frames, in millimetres.
std::string ThreeBodies() {
  std::string types, names, kinds, axes;
  const char* bodies[] = {"Robot", "Scanner", "Part"};
  for (const char* b : bodies) {
    for (int i = 0; i < 7; ++i) {
      types += ",Rigid Body";
      names += std::string(",") + b;
      kinds += i < 4 ? ",Rotation" : ",Position";
      axes += std::string(",") + "XYZWXYZ"[i];
    }
  }
  std::string text = "Format Version,1.23,Take Name,S_04,Capture Frame Rate,120.000000,Rotation Type,Quaternion,"
                     "Length Units,Millimeters,Coordinate Space,Global\n\n,Type" + types + "\n,Name" + names +
                     "\n,ID" + std::string(21, ',') + "\n," + kinds + "\nFrame,Time (Seconds)" + axes + "\n";
  for (int k = 0; k < 2; ++k) {
    std::vector<double> v = {double(k), 0.008333 * k};
    for (int b = 0; b < 3; ++b) {
      const Pose p = BodyPose(b, k);
      const Eigen::Quaterniond q(p.linear());
      const Eigen::Vector3d t = p.translation() * 1000;
      v.insert(v.end(), {q.x(), q.y(), q.z(), q.w(), t.x(), t.y(), t.z()});
    }
    text += Join(v) + "\n";
  }
  return text;
}

TEST(PoseFileBodies, MotiveRigidBodyChosenByName) {
  PoseFileOptions o;
  o.body = "Scanner";
  const PoseFile s = ParsePoseFile(ThreeBodies(), "take.csv", o);
  ExpectPoses(s);
  EXPECT_EQ(s.units, PoseUnits::kMillimetres);
  EXPECT_THAT(s.form, HasSubstr("OptiTrack Motive rigid body 'Scanner'"));
  o.body = "Part";
  const PoseFile p = ParsePoseFile(ThreeBodies(), "take.csv", o);
  ASSERT_EQ(p.poses.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    EXPECT_LT((p.poses[size_t(k)].matrix() - BodyPose(2, k).matrix()).cwiseAbs().maxCoeff(), 1e-12);
  }
  // Without the option, several bodies; a name not in the file: the Name row, every body.
  EXPECT_EQ(ErrorOf(ThreeBodies()), "poses.csv:4: an OptiTrack Motive export of several rigid bodies: give "
                                    "--pose-body: 'Robot', 'Scanner', 'Part'");
  o.body = "scanner";
  EXPECT_EQ(ErrorOf(ThreeBodies(), o), "poses.csv:4: no rigid body 'scanner' in this OptiTrack Motive export: its "
                                       "rigid bodies are 'Robot', 'Scanner', 'Part'");
}

// rostopic echo -p of a geometry_msgs/TransformStamped topic broadcast for two frames.
std::string TfRows(const std::vector<std::string>& frames) {
  std::string text = "%time,field.header.seq,field.header.stamp,field.header.frame_id,field.child_frame_id,"
                     "field.transform.translation.x,field.transform.translation.y,field.transform.translation.z,"
                     "field.transform.rotation.x,field.transform.rotation.y,field.transform.rotation.z,"
                     "field.transform.rotation.w\n";
  for (int k = 0; k < 2; ++k) {
    for (size_t f = 0; f < frames.size(); ++f) {
      const Pose p = BodyPose(int(f) + 1, k);
      const std::string stamp = std::to_string(1700000000000000000LL + k * 100000000LL + int(f) * 1000000LL);
      text += stamp + "," + std::to_string(k) + "," + stamp + ",world," + frames[f] + "," +
              Join(Xyzw(p, p.translation())) + "\n";
    }
  }
  return text;
}

TEST(PoseFileBodies, RosChildFrameRowsChosenByName) {
  PoseFileOptions o;
  o.body = "scanner";
  const PoseFile s = ParsePoseFile(TfRows({"scanner", "part"}), "tf.csv", o);
  ExpectPoses(s);
  EXPECT_EQ(s.lines, (std::vector<int>{2, 4}));
  ASSERT_EQ(s.times_s.size(), 2u);
  EXPECT_NEAR(s.times_s[1] - s.times_s[0], 0.1, 1e-6);
  EXPECT_THAT(s.form, HasSubstr("child frame 'scanner'"));
  // Read before without a word, the two frames' rows mixed in one trajectory of 4 poses.
  EXPECT_EQ(ErrorOf(TfRows({"scanner", "part"})),
            "poses.csv:3: rows of several child frames (column 5 'field.child_frame_id'), mixed in one trajectory if "
            "read: give --pose-body: 'scanner', 'part'");
  o.body = "robot";
  EXPECT_EQ(ErrorOf(TfRows({"scanner", "part"}), o),
            "poses.csv:1: no rows of the child frame 'robot' (column 5 'field.child_frame_id'): its rows are of "
            "'scanner', 'part'");
  // One child frame (an Odometry's base_link) reads without the option, or with its name.
  ExpectPoses(ParsePoseFile(TfRows({"scanner"}), "tf.csv"));
  o.body = "scanner";
  ExpectPoses(ParsePoseFile(TfRows({"scanner"}), "tf.csv", o));
  // Two bodies in one row (a tf message of two transforms, PlotJuggler's columns per frame): refused as before.
  EXPECT_THAT(ErrorOf("field.transforms0.child_frame_id,field.transforms0.transform.translation.x,"
                      "field.transforms1.child_frame_id,field.transforms1.transform.translation.x\n"),
              HasSubstr("a second child frame column"));
  EXPECT_THAT(ErrorOf("__time,/tf/world/scanner/translation/x,/tf/world/part/translation/x\n"),
              HasSubstr("column 3 '/tf/world/part/translation/x': a second column for the same value"));
  // A file naming no bodies.
  EXPECT_EQ(ErrorOf(Rows("x,y,z,qx,qy,qz,qw", ",", 1, [](const Pose& p, const Eigen::Vector3d& t, int) {
                      return Xyzw(p, t);
                    }),
                    o),
            "poses.csv: --pose-body 'scanner': the file names no bodies (--pose-body picks an OptiTrack Motive "
            "export's rigid body, or the rows of one child_frame_id)");
}

}  // namespace
}  // namespace lt
