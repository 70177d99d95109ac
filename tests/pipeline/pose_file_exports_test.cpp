// Pose files as ROS 2 bag exports, PlotJuggler and robot logs write them, second pass
// (docs/pipeline.md, "Real logs checked"): a stamp in two columns, names holding a
// separator, Franka's column-major O_T_EE, and exports refused with what to write instead.
#include "pipeline/pose_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/error.h"
#include "pose_file_test_util.h"

namespace lt {
namespace {

using ::testing::HasSubstr;
using namespace pose_file_test;

std::string XyzQuaternion(const Pose& p) {
  const Eigen::Quaterniond q(p.linear());
  return Join({p.translation().x(), p.translation().y(), p.translation().z(), q.x(), q.y(), q.z(), q.w()});
}

TEST(PoseFile, RosStampInSecondsAndNanosecondsIsOneTime) {
  // A ROS 2 bag exported to CSV (rosbags, ros2 bag to CSV scripts): header.stamp.sec and .nanosec.
  const PoseFile f = ParsePoseFile(
      Log("timestamp,header.stamp.sec,header.stamp.nanosec,header.frame_id,pose.position.x,pose.position.y,"
          "pose.position.z,pose.orientation.x,pose.orientation.y,pose.orientation.z,pose.orientation.w",
          [](const Pose& p, int k) {
            return "1700000000300000000,1700000000," + std::to_string(123456789 + 250000000 * k) + ",map," +
                   XyzQuaternion(p);
          }),
      "ros2.csv");
  ExpectPoses(f);
  ASSERT_EQ(f.times_s.size(), 2u);
  // The message's stamp, not the bag's receive time; 1.7e9 s + ns in a double: to 0.24 us.
  EXPECT_NEAR(f.times_s[0], 1700000000.123456789, 3e-7);
  EXPECT_NEAR(f.times_s[1] - f.times_s[0], 0.25, 5e-7);
  EXPECT_THAT(f.form, HasSubstr("CSV columns header.stamp.sec,header.stamp.nanosec,pose.position.x"));
  // ROS 1 (bagpy's CSV): secs and nsecs; a file of '_'-joined names: _sec and _nsec.
  for (const std::string header : {"Time,header.seq,header.stamp.secs,header.stamp.nsecs,header.frame_id,"
                                   "pose.position.x,pose.position.y,pose.position.z,pose.orientation.x,"
                                   "pose.orientation.y,pose.orientation.z,pose.orientation.w",
                                   "Time,seq,stamp_sec,stamp_nsec,frame_id,x,y,z,qx,qy,qz,qw"}) {
    const PoseFile g = ParsePoseFile(Log(header,
                                         [](const Pose& p, int k) {
                                           return "99.5,7,1624114603," + std::to_string(5000000 * k) + ",odom," +
                                                  XyzQuaternion(p);
                                         }),
                                     "ros1.csv");
    ExpectPoses(g);
    ASSERT_EQ(g.times_s.size(), 2u) << header;
    EXPECT_NEAR(g.times_s[1], 1624114603.005, 3e-7) << header;
  }
  // One part of a stamp without the other is no time; "time_sec" or "timestamp_nsec" alone is one.
  EXPECT_THAT(ErrorOf("header.stamp.sec,x,y,z,qx,qy,qz,qw\n"),
              HasSubstr("a time's seconds without its nanoseconds column (header.stamp"));
  EXPECT_EQ(ParsePoseFile("time_sec,x,y,z,qx,qy,qz,qw\n12.5,0,0,0,0,0,0,1\n", "p").times_s[0], 12.5);
  EXPECT_EQ(ParsePoseFile("timestamp_nsec,x,y,z,qx,qy,qz,qw\n12500000000,0,0,0,0,0,0,1\n", "p").times_s[0], 12.5);
}

TEST(PoseFile, PlotJugglerStampIsInSecondsAndCovarianceNamesDoNotSplit) {
  // PlotJuggler writes a message's header stamp in seconds and a covariance's elements as
  // "[i;j]": the ';' inside the brackets separates nothing.
  // A PoseStamped as PlotJuggler exports it: the stamp in seconds (read as ns before: 1.6 s), the
  // quaternion's roll, pitch and yaw in degrees beside it (an unknown column before).
  const PoseFile stamped = ParsePoseFile(
      Log("__time,/vicon/pose/header/stamp,/vicon/pose/pose/position/x,/vicon/pose/pose/position/y,"
          "/vicon/pose/pose/position/z,/vicon/pose/pose/orientation/x,/vicon/pose/pose/orientation/y,"
          "/vicon/pose/pose/orientation/z,/vicon/pose/pose/orientation/w,/vicon/pose/pose/orientation/roll_deg,"
          "/vicon/pose/pose/orientation/pitch_deg,/vicon/pose/pose/orientation/yaw_deg",
          [](const Pose& p, int k) {
            return Join({1624114604.5 + k, 1624114603.25 + k}) + "," + XyzQuaternion(p) + ",10,20,30";
          }),
      "pj.csv");
  ExpectPoses(stamped);
  ASSERT_EQ(stamped.times_s.size(), 2u);
  EXPECT_NEAR(stamped.times_s[0], 1624114603.25, 1e-6);
  // Without the quaternion, its angles are no rotation read here.
  EXPECT_THAT(ErrorOf("x,y,z,/p/orientation/roll_deg,/p/orientation/pitch_deg,/p/orientation/yaw_deg\n"),
              HasSubstr("column 4 '/p/orientation/roll_deg': unknown column name"));
  std::string header = "__time,/odom/header/stamp,/odom/pose/position/x,/odom/pose/position/y,/odom/pose/position/z,"
                       "/odom/pose/orientation/x,/odom/pose/orientation/y,/odom/pose/orientation/z,"
                       "/odom/pose/orientation/w";
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) header += ",/odom/pose/covariance[" + std::to_string(i) + ";" + std::to_string(j) + "]";
  }
  header += ",\"/odom/twist/covariance[0,0]\"";  // quoted, with a comma: one field
  const PoseFile f = ParsePoseFile(Log(header,
                                       [](const Pose& p, int k) {
                                         std::string row = Join({1624114604.5 + 0.01 * k, 1624114603.25 + 0.01 * k}) +
                                                           "," + XyzQuaternion(p);
                                         for (int i = 0; i < 22; ++i) row += ",0.01";
                                         return row;
                                       }),
                                   "pj.csv");
  ExpectPoses(f);
  ASSERT_EQ(f.times_s.size(), 2u);
  EXPECT_NEAR(f.times_s[0], 1624114603.25, 1e-6);  // the header's stamp, in seconds
  EXPECT_THAT(f.form, HasSubstr("23 others skipped"));
  // Other bag-to-CSV tools write the topic path's stamp in ns (ros1_msg_to_csv's README): read by its size.
  EXPECT_NEAR(ParsePoseFile("/header/frame_id,/header/stamp,/pose/position/x,/pose/position/y,/pose/position/z,"
                            "/pose/orientation/x,/pose/orientation/y,/pose/orientation/z,/pose/orientation/w\n"
                            "base_link,1628123456789012345,0,0,0,0,0,0,1\n",
                            "p")
                  .times_s[0],
              1628123456.789012, 1e-5);
  // rostopic echo -p's field.header.stamp stays in ns.
  EXPECT_NEAR(ParsePoseFile("field.header.stamp,x,y,z,qx,qy,qz,qw\n1624114603250000000,0,0,0,0,0,0,1\n", "p")
                  .times_s[0],
              1624114603.25, 1e-6);
}

TEST(PoseFile, FrankaLogReadsItsColumnMajorEndEffectorPose) {
  // franka_msgs/FrankaState through rostopic echo -p: O_T_EE0..15 column-major, its desired and
  // commanded poses, the flange and stiffness frames, joints and forces skipped.
  auto column_major = [](const Pose& p) {
    std::vector<double> v;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) v.push_back(p.matrix()(r, c));
    return v;
  };
  std::string header = "%time,field.header.seq,field.header.stamp,field.header.frame_id";
  for (const char* name : {"O_T_EE", "O_T_EE_d", "F_T_EE", "EE_T_K"}) {
    for (int k = 0; k < 16; ++k) header += std::string(",field.") + name + std::to_string(k);
  }
  for (int k = 0; k < 7; ++k) header += ",field.q" + std::to_string(k) + ",field.tau_J" + std::to_string(k);
  header += ",field.time,field.robot_mode";
  const PoseFile f = ParsePoseFile(Log(header,
                                       [&](const Pose& p, int k) {
                                         std::vector<double> v{1.0 + k, double(k), 1.0e9 + 1e6 * k};
                                         std::string row = Join(v) + ",panda_link0," + Join(column_major(p));
                                         row += ',';
                                         row += Join(column_major(TestPose(5)));  // O_T_EE_d: not read
                                         for (int i = 0; i < 32 + 14; ++i) row += ",0.5";
                                         return row + ",12.5,2";
                                       }),
                                   "franka_states.csv");
  ExpectPoses(f);
  EXPECT_EQ(f.units, PoseUnits::kMetres);
  EXPECT_THAT(f.form, HasSubstr("(Franka O_T_EE, column-major)"));
  // libfranka's O_T_EE[k] names (its logToCSV's form), in the PlotJuggler topic path too.
  for (const std::string prefix : {"state.O_T_EE", "/franka_state_controller/franka_states/O_T_EE"}) {
    std::string names = "time";
    for (int k = 0; k < 16; ++k) names += "," + prefix + "[" + std::to_string(k) + "]";
    ExpectPoses(ParsePoseFile(Log(names, [&](const Pose& p, int k) { return std::to_string(k) + "," + Join(column_major(p)); }),
                              "franka.csv"));
  }
  // Written row-major by mistake: its last row is not 0 0 0 1.
  std::string names = "time";
  for (int k = 0; k < 16; ++k) names += ",O_T_EE[" + std::to_string(k) + "]";
  EXPECT_THAT(ErrorOf(Log(names,
                          [&](const Pose& p, int k) {
                            std::vector<double> v;
                            for (int r = 0; r < 4; ++r)
                              for (int c = 0; c < 4; ++c) v.push_back(p.matrix()(r, c));
                            return std::to_string(k) + "," + Join(v);
                          })),
              HasSubstr("poses.csv:2: the last row of a 4x4 pose must be 0 0 0 1"));
  // libfranka's logToCSV holds the commanded pose only; an element missing.
  std::string commanded = "time,success_rate";
  for (int k = 0; k < 16; ++k) commanded += ",cmd.O_T_EE_d[" + std::to_string(k) + "]";
  EXPECT_THAT(ErrorOf(commanded + "\n"), HasSubstr("poses.csv:1: column 3 'cmd.O_T_EE_d[0]': a Franka log of the commanded pose only"));
  EXPECT_THAT(ErrorOf("O_T_EE[0],O_T_EE[5]\n"), HasSubstr("Franka's O_T_EE needs its 16 elements, got 2"));
}

TEST(PoseFile, ExportsOfUnknownConventionAreRefusedSayingWhatToWrite) {
  // Qualisys QTM's TSV 6D export: its Euler angles' definition is a QTM setting, not in the file.
  EXPECT_THAT(ErrorOf("NO_OF_FRAMES\t2\nNO_OF_CAMERAS\t8\nFREQUENCY\t100\nDATA_INCLUDED\t6D\n"),
              HasSubstr("poses.csv:1: column 1 'NO_OF_FRAMES': a Qualisys QTM TSV export"));
  // COLMAP's images.txt: camera_from_world, two lines per image.
  EXPECT_THAT(ErrorOf("# Image list with two lines of data per image:\n#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, "
                      "CAMERA_ID, NAME\n1 1 0 0 0 0 0 0.1 1 a.png\n10.5 20.5 -1\n"),
              HasSubstr("poses.csv:1: COLMAP's images.txt is not read as poses: its QW QX QY QZ TX TY TZ are "
                        "camera_from_world"));
  // nerfstudio's transforms.json: camera-to-world in OpenGL camera axes.
  EXPECT_THAT(ErrorOf("{\n  \"camera_model\": \"OPENCV\",\n  \"frames\": []\n}\n"),
              HasSubstr("poses.csv:1: column 1 '{': a JSON file is not read as poses"));
}

}  // namespace
}  // namespace lt
