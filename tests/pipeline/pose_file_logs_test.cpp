// Pose files as real logs hold them (docs/pipeline.md, "Real logs checked"), in tiny
// hand-written excerpts of each form: the pose columns read, the other quantities
// skipped, what might be another pose refused.
#include "pipeline/pose_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/error.h"
#include "pose_file_test_util.h"

namespace lt {
namespace {

using ::testing::HasSubstr;
using namespace pose_file_test;

TEST(PoseFile, EurocGroundTruthSkipsVelocitiesAndBiases) {
  // mav0/state_groundtruth_estimate0/data.csv: a '#' header with units, w first, ns times.
  const PoseFile f = ParsePoseFile(
      Log("#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z [], "
          "v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], "
          "b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]",
          [](const Pose& p, int k) {
            const Eigen::Quaterniond q(p.linear());
            const Eigen::Vector3d t = p.translation();
            return std::to_string(1403715524922140000LL + 25000000LL * k) + "," +
                   Join({t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z(), 7, 8, 9, -0.002, 0.02, 0.07, -0.01, 0.1, 0.09});
          }),
      "data.csv");
  ExpectPoses(f);
  ASSERT_EQ(f.times_s.size(), 2u);
  EXPECT_NEAR(f.times_s[1] - f.times_s[0], 0.025, 1e-6);
  EXPECT_NEAR(f.times_s[0], 1403715524.92214, 1e-5);
  EXPECT_THAT(f.form, HasSubstr("9 others skipped, times in ns"));
  // TUM-VI's: the unit in the time's name.
  EXPECT_NEAR(ParsePoseFile("#timestamp [ns], p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], "
                            "q_RS_y [], q_RS_z []\n1520530308189679351,0.84,-0.22,1.25,1,0,0,0\n",
                            "room1.csv")
                  .times_s[0],
              1520530308.189679, 1e-5);
  // A time column said to be in seconds stays in seconds, however large.
  EXPECT_EQ(ParsePoseFile("t [s],x,y,z,qx,qy,qz,qw\n1e18,0,0,0,0,0,0,1\n", "p").times_s[0], 1e18);
}

TEST(PoseFile, RosTopicCsvReadsThePoseAndTheHeaderStamp) {
  auto quaternion = [](const Pose& p) {
    const Eigen::Quaterniond q(p.linear());
    return Join({p.translation().x(), p.translation().y(), p.translation().z(), q.x(), q.y(), q.z(), q.w()});
  };
  // rostopic echo -p of a PoseStamped: %time (recorded) and header.stamp (the message's), ns; frame_id text.
  const PoseFile stamped = ParsePoseFile(
      Log("%time,field.header.seq,field.header.stamp,field.header.frame_id,field.pose.position.x,field.pose.position.y,"
          "field.pose.position.z,field.pose.orientation.x,field.pose.orientation.y,field.pose.orientation.z,"
          "field.pose.orientation.w",
          [&](const Pose& p, int k) {
            return std::to_string(175447000000LL + 9000000LL + k) + "," + std::to_string(5 + k) + "," +
                   std::to_string(175447000000LL + 20000000LL * k) + ",map," + quaternion(p);
          }),
      "pose.csv");
  ExpectPoses(stamped);
  EXPECT_EQ(stamped.times_s, (std::vector<double>{175.447, 175.467}));
  // An Odometry: covariances and the twist skipped.
  std::string odometry = "%time,field.header.seq,field.header.stamp,field.header.frame_id,field.child_frame_id,"
                         "field.pose.pose.position.x,field.pose.pose.position.y,field.pose.pose.position.z,"
                         "field.pose.pose.orientation.x,field.pose.pose.orientation.y,field.pose.pose.orientation.z,"
                         "field.pose.pose.orientation.w";
  for (int i = 0; i < 36; ++i) odometry += ",field.pose.covariance" + std::to_string(i);
  odometry += ",field.twist.twist.linear.x,field.twist.twist.linear.y,field.twist.twist.linear.z,"
              "field.twist.twist.angular.x,field.twist.twist.angular.y,field.twist.twist.angular.z";
  for (int i = 0; i < 36; ++i) odometry += ",field.twist.covariance" + std::to_string(i);
  ExpectPoses(ParsePoseFile(Log(odometry,
                                [&](const Pose& p, int k) {
                                  std::string r = "1664948325587996960," + std::to_string(k) +
                                                  ",1739641583660682927,/camera_init,/laser_odom," + quaternion(p);
                                  for (int i = 0; i < 78; ++i) r += ",0.5";
                                  return r;
                                }),
                            "odom.csv"));
  // ros2 topic echo --csv: no header; with the header its error asks for, read by row.
  EXPECT_THAT(ErrorOf("1700000000,123456789,map,0.3,0.1,0.5,0,0,0,1\n"),
              HasSubstr("poses.csv:1: column 1 '1700000000': a number where a column's name belongs"));
  ExpectPoses(ParsePoseFile(Log("header.stamp.sec,header.stamp.nanosec,header.frame_id,x,y,z,qx,qy,qz,qw",
                                [&](const Pose& p, int k) {
                                  return "1700000000," + std::to_string(123456789 + k) + ",map," + quaternion(p);
                                }),
                            "ros2.csv"));
  // A tf message's first transform.
  ExpectPoses(ParsePoseFile(
      Log("%time,field.transforms0.header.seq,field.transforms0.header.stamp,field.transforms0.header.frame_id,"
          "field.transforms0.child_frame_id,field.transforms0.transform.translation.x,"
          "field.transforms0.transform.translation.y,field.transforms0.transform.translation.z,"
          "field.transforms0.transform.rotation.x,field.transforms0.transform.rotation.y,"
          "field.transforms0.transform.rotation.z,field.transforms0.transform.rotation.w",
          [&](const Pose& p, int k) {
            return "1739641583661579370,0," + std::to_string(1739641583660682927LL + k) + ",camera_init,aft_mapped," +
                   quaternion(p);
          }),
      "tf.csv"));
}

TEST(PoseFile, PlotJugglerCsvReadsTopicPaths) {
  const std::string header =
      "__time,/vicon/pose/header/seq,/vicon/pose/pose/position/x,/vicon/pose/pose/position/y,"
      "/vicon/pose/pose/position/z,/vicon/pose/pose/orientation/x,/vicon/pose/pose/orientation/y,"
      "/vicon/pose/pose/orientation/z,/vicon/pose/pose/orientation/w,/odom/twist/linear/x";
  auto row = [](const Pose& p, int k) {
    const Eigen::Quaterniond q(p.linear());
    const Eigen::Vector3d t = p.translation();
    return Join({1624114603.333 + 0.01 * k, double(k), t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w(), 0.5});
  };
  const PoseFile f = ParsePoseFile(Log(header, row), "pj.csv");
  ExpectPoses(f);
  ASSERT_EQ(f.times_s.size(), 2u);
  EXPECT_NEAR(f.times_s[1] - f.times_s[0], 0.01, 1e-6);
  // A row of another topic leaves the pose's cells empty.
  EXPECT_THAT(ErrorOf(header + "\n1624114603.334,,,,,,,,,1452\n"), HasSubstr("poses.csv:2: field 3 is empty"));
}

TEST(PoseFile, UniversalRobotsRtdeLogReadsTheActualTcpPose) {
  // A real RTDE record's columns (joints, currents, speeds, the commanded target pose, a repeated name).
  std::string header = "timestamp";
  for (const char* f : {"actual_q", "target_current", "target_current", "actual_TCP_pose", "actual_TCP_speed",
                        "target_TCP_pose", "joint_temperatures"}) {
    for (int i = 0; i < 6; ++i) header += std::string(",") + f + "_" + std::to_string(i);
  }
  header += ",actual_execution_time,robot_mode,safety_status,speed_scaling";
  const PoseFile f = ParsePoseFile(Log(header,
                                       [](const Pose& p, int k) {
                                         const Eigen::AngleAxisd aa(p.linear());
                                         const Eigen::Vector3d r = aa.axis() * aa.angle();
                                         const Eigen::Vector3d t = p.translation();
                                         std::vector<double> v{4156.212 + 0.008 * k};
                                         for (int i = 0; i < 18; ++i) v.push_back(0.1 * i);
                                         for (double x : {t.x(), t.y(), t.z(), r.x(), r.y(), r.z()}) v.push_back(x);
                                         for (int i = 0; i < 6; ++i) v.push_back(0.01);
                                         for (int i = 0; i < 6; ++i) v.push_back(0.3 + i);  // the target: not read
                                         for (int i = 0; i < 6; ++i) v.push_back(25.5);
                                         for (double x : {0.17, 7.0, 1.0, 1.0}) v.push_back(x);
                                         return Join(v);
                                       }),
                                   "robot_data.csv");
  ExpectPoses(f);
  EXPECT_EQ(f.units, PoseUnits::kMetres);
  EXPECT_THAT(f.form, HasSubstr("actual_tcp_pose_5, 40 others skipped"));
  // A planned path in the RTDE log's form: its target_TCP_pose is the only pose.
  std::string planned = "timestamp";
  for (const char* c : {"target_q", "target_TCP_pose"}) {
    for (int i = 0; i < 6; ++i) planned += std::string(" ") + c + "_" + std::to_string(i);
  }
  ExpectPoses(ParsePoseFile(Log(planned,
                                [](const Pose& p, int k) {
                                  const Eigen::AngleAxisd aa(p.linear());
                                  const Eigen::Vector3d r = aa.axis() * aa.angle(), t = p.translation();
                                  return Join({0.008 * k, 1, 2, 3, 4, 5, 6, t.x(), t.y(), t.z(), r.x(), r.y(), r.z()},
                                              " ");
                                }),
                            "planned.csv"));
}

TEST(PoseFile, KukaRsiLogReadsTheActualPose) {
  // A real RSI log's columns: RIst (actual, mm and degrees), RSol (setpoint), process signals; a date.
  const PoseFile f = ParsePoseFile(
      Log("Timestamp,X_RIst,Y_RIst,Z_RIst,A_RIst,B_RIst,C_RIst,X_RSol,Y_RSol,Z_RSol,A_RSol,B_RSol,C_RSol,Delay,"
          "WeldVolt,WeldAmps,IPOC,ErrorNum,C11,i1",
          [](const Pose& p, int) {
            const Eigen::Vector3d zyx = p.linear().eulerAngles(2, 1, 0) * (180 / M_PI);
            const Eigen::Vector3d t = p.translation() * 1000;
            return "2024-09-24 14:05:15," + Join({t.x(), t.y(), t.z(), zyx[0], zyx[1], zyx[2], 1279.5, 192.2, 977.3,
                                                  80.5, 60.3, 116.8, 0, 14417, 12320, 1210441551, 0, 0.0, 1});
          }),
      "robot_data.csv");
  ExpectPoses(f);
  EXPECT_EQ(f.units, PoseUnits::kMillimetres);
  EXPECT_TRUE(f.times_s.empty());  // a date: the rows go by frame
  // Its actual pose beside plain X,Y,Z columns: two translations.
  EXPECT_THAT(ErrorOf("X,Y,Z,A,B,C,X_RIst\n"), HasSubstr("column 7 'X_RIst': a second column for the same value"));
}

// An OptiTrack Motive export (format 1.23's rows): the one rigid body's columns.
std::string Motive(const std::string& settings, const std::string& types, const std::string& names) {
  return "Format Version,1.23,Take Name,S_04,Take Notes,,Capture Frame Rate,120.000000," + settings + "\n\n" +
         ",Type," + types + "\n,Name," + names + "\n,ID,1,1,1,1,1,1,1,1,2,2,2\n"
         ",,Rotation,Rotation,Rotation,Rotation,Position,Position,Position,Mean Marker Error,Position,Position,"
         "Position\nFrame,Time (Seconds),X,Y,Z,W,X,Y,Z,,X,Y,Z,,\n";
}

TEST(PoseFile, OptiTrackMotiveExportReadsItsRigidBody) {
  const std::string body = "Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body";
  const std::string rows = Rows("", ",", 1000, [](const Pose& p, const Eigen::Vector3d& t, int k) {
    const Eigen::Quaterniond q(p.linear());
    return std::vector<double>{double(k), 0.008333 * k, q.x(), q.y(), q.z(), q.w(), t.x(), t.y(), t.z(), 0.0002,
                               1.5, 2.5, 3.5};
  });
  std::string trailing;  // Motive's empty cells at the end of each row
  for (size_t a = 0, b; (b = rows.find('\n', a)) != std::string::npos; a = b + 1) trailing += rows.substr(a, b - a) + ",,\n";
  const std::string settings = "Rotation Type,Quaternion,Length Units,Millimeters,Coordinate Space,Global";
  const PoseFile f = ParsePoseFile(
      Motive(settings, body + ",Marker,Marker,Marker", "Scanner,Scanner,Scanner,Scanner,Scanner,Scanner,Scanner,"
                                                     "Scanner,Unlabeled 1,Unlabeled 1,Unlabeled 1") + trailing,
      "take.csv");
  ExpectPoses(f);
  EXPECT_EQ(f.units, PoseUnits::kMillimetres);
  EXPECT_NEAR(f.times_s[1], 0.008333, 1e-12);
  EXPECT_THAT(f.form, HasSubstr("OptiTrack Motive rigid body 'Scanner'"));
  // Two rigid bodies: which is the scanner's? Euler angles, centimetres, markers only: refused.
  EXPECT_THAT(ErrorOf(Motive(settings, body + ",Rigid Body,Rigid Body,Rigid Body",
                             "A,A,A,A,A,A,A,A,B,B,B") + trailing),
              HasSubstr("poses.csv:4: an OptiTrack Motive export of several rigid bodies: give --pose-body: 'A', 'B'"));
  EXPECT_THAT(ErrorOf(Motive("Rotation Type,XYZ,Length Units,Meters", body + ",Marker,Marker,Marker",
                             "A,A,A,A,A,A,A,A,m,m,m") + trailing),
              HasSubstr("poses.csv:1: an OptiTrack Motive export with Rotation Type xyz"));
  EXPECT_THAT(ErrorOf(Motive("Rotation Type,Quaternion,Length Units,Centimeters", body + ",Marker,Marker,Marker",
                             "A,A,A,A,A,A,A,A,m,m,m") + trailing),
              HasSubstr("export in meters or millimeters"));
  EXPECT_THAT(ErrorOf(Motive(settings, "Marker,Marker,Marker,Marker,Marker,Marker,Marker,Marker,Marker,Marker,Marker",
                             "m,m,m,m,m,m,m,m,m,m,m") + trailing),
              HasSubstr("poses.csv:3: an OptiTrack Motive export without a rigid body"));
  // A frame the tracker lost: empty cells.
  EXPECT_THAT(ErrorOf(Motive(settings, body + ",Marker,Marker,Marker", "A,A,A,A,A,A,A,A,m,m,m") +
                      "0,0,,,,,,,,,1,2,3,,\n"),
              HasSubstr("poses.csv:8: field 3 is empty (a frame the tracker lost"));
}

TEST(PoseFile, AbbTargetsSkipTheirConfigurationAndMoveData) {
  // Robtargets as a public RAPID converter's CSVs hold them: mm, q1..q4, robconf, the move's data.
  auto abb = [](const Pose& p, int k) {
    const Eigen::Quaterniond q(p.linear());
    const Eigen::Vector3d t = p.translation() * 1000;
    std::string target = "p";
    target += std::to_string(k);
    return target + "," + Join({t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z(), 0, -1, 0, 0}) +
           ",MoveL,v500,z10";
  };
  PoseFileOptions mm;
  mm.units = PoseUnits::kMillimetres;
  ExpectPoses(ParsePoseFile(Log("name,x,y,z,q1,q2,q3,q4,cf1,cf4,cf6,cfx,move_type,speed,zone", abb), "targets.csv", mm));
  // A tool or work object may change the frame from row to row: not skipped.
  EXPECT_THAT(ErrorOf("x,y,z,q1,q2,q3,q4,move_type,speed,zone,tool,wobj\n"),
              HasSubstr("column 11 'tool': unknown column name"));
  EXPECT_THAT(ErrorOf("x,y,z,q1,q2,q3,q4,eax_a\n"), HasSubstr("column 8 'eax_a': unknown column name"));
}

TEST(PoseFile, ColumnsThatMightBeAnotherPoseAreRefused) {
  // A column that could be a second pose or rotation is no column to skip.
  EXPECT_THAT(ErrorOf("x,y,z,qx,qy,qz,qw,x2\n"), HasSubstr("poses.csv:1: column 8 'x2': unknown column name"));
  EXPECT_THAT(ErrorOf("field.pose.position.x,field.pose.position.y,field.pose.position.z,field.pose.orientation.x,"
                      "field.pose.orientation.y,field.pose.orientation.z,field.pose.orientation.w,"
                      "field.target.position.x\n"),
              HasSubstr("column 8 'field.target.position.x': a second column for the same value"));
  EXPECT_THAT(ErrorOf("#timestamp,p_RS_R_x,p_RS_R_y,p_RS_R_z,q_RS_w,q_RS_x,q_RS_y,q_RS_z,q_RB_w\n"
                      "1,0,0,0,1,0,0,0,1\n"),
              HasSubstr("poses.csv:2: 9 numbers per row"));  // the '#' header is not taken: no header at all
  EXPECT_THAT(ErrorOf("time,seq,pose_b_x,x,y,z,qx,qy,qz,qw\n"), HasSubstr("column 3 'pose_b_x': unknown column name"));
  // Two message times of the same kind.
  EXPECT_THAT(ErrorOf("a.header.stamp,b.header.stamp,x,y,z,qx,qy,qz,qw\n"),
              HasSubstr("column 2 'b.header.stamp': a second time column"));
  // Vicon's multi-row export: refused, saying what to write instead.
  EXPECT_THAT(ErrorOf("Segments\n100\n,,Probe:Probe\nFrame,Sub Frame,RX,RY,RZ,TX,TY,TZ\n,,deg,deg,deg,mm,mm,mm\n"),
              HasSubstr("poses.csv:1: column 1 'Segments': a Vicon Nexus export"));
  // Its rows under their own column names: RX RY RZ are degrees, no rotation vector.
  EXPECT_THAT(ErrorOf("Frame,Sub Frame,RX,RY,RZ,TX,TY,TZ\n1,0,0.0,0.0,90.0071,1.0,2.0,3.0\n"),
              HasSubstr("Vicon's RX RY RZ (beside its Sub Frame) are angles in degrees"));
  // Angles in degrees given as a rotation vector.
  EXPECT_THAT(ErrorOf("x,y,z,rx,ry,rz\n0,0,0,0,0,90\n"),
              HasSubstr("poses.csv:2: a rotation vector of 90 rad (more than 2 pi): angles in degrees?"));
}

}  // namespace
}  // namespace lt
