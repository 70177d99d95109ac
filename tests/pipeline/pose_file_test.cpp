// Pose files as robots, printers and tracking tools write them
// (pipeline/pose_file.h): every form gives the same poses; each bad input is an
// InputError naming the file and line.
#include "pipeline/pose_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>

#include "core/error.h"
#include "pose_file_test_util.h"

namespace lt {
namespace {

using ::testing::HasSubstr;
using namespace pose_file_test;

TEST(PoseFile, EveryFormGivesThePoses) {
  auto xyzw = [](const Pose& p, const Eigen::Vector3d& t, int) { return Xyzw(p, t); };
  auto wxyz = [](const Pose& p, const Eigen::Vector3d& t, int) { return Wxyz(p, t); };
  ExpectPoses(ParsePoseFile(Rows("x,y,z,qx,qy,qz,qw", ",", 1, xyzw), "p"));
  ExpectPoses(ParsePoseFile(Rows("x; y; z; qw; qx; qy; qz", ";", 1, wxyz), "p"));
  ExpectPoses(ParsePoseFile(Rows("# tx ty tz qw qx qy qz", " ", 1, wxyz), "p"));  // a commented header
  ExpectPoses(ParsePoseFile(Rows("x,y,z,q1,q2,q3,q4", ",", 1, wxyz), "p"));        // ABB: w first
  ExpectPoses(ParsePoseFile(Rows("\"x\",\"y\",\"z\",\"qx\",\"qy\",\"qz\",\"qw\"", ",", 1, xyzw), "p"));  // quoted
  PoseFileOptions o;
  o.order = QuaternionOrder::kWxyz;
  ExpectPoses(ParsePoseFile(Rows("", ",", 1, wxyz), "p", o));
  o.order = QuaternionOrder::kXyzw;
  ExpectPoses(ParsePoseFile(Rows("", ",", 1, xyzw), "p", o));
  // Columns in any order, with time and image columns skipped; units in the names.
  const PoseFile named = ParsePoseFile(Rows("image,t_s,qw,qx,qy,qz,x [mm],y [mm],z [mm]", ",", 1000,
                                            [](const Pose& p, const Eigen::Vector3d& t, int k) {
                                              const Eigen::Quaterniond q(p.linear());
                                              return std::vector<double>{double(k), 0.1 * k, q.w(), q.x(), q.y(),
                                                                         q.z(), t.x(), t.y(), t.z()};
                                            }),
                                       "p");
  ExpectPoses(named);
  EXPECT_EQ(named.units, PoseUnits::kMillimetres);
  // TUM: timestamp tx ty tz qx qy qz qw, blank separated, comments.
  const PoseFile tum = ParsePoseFile("# ground truth\n" + Rows("", " ", 1, [](const Pose& p, const Eigen::Vector3d& t, int k) {
    std::vector<double> v = Xyzw(p, t);
    v.insert(v.begin(), 1700000000.5 + k);
    return v;
  }), "p");
  ExpectPoses(tum);
  EXPECT_THAT(tum.form, HasSubstr("TUM"));
  // 3x4 and 4x4 row-major matrices.
  auto matrix = [](int rows) {
    return [rows](const Pose& p, const Eigen::Vector3d&, int) {
      std::vector<double> v;
      for (int i = 0; i < rows; ++i)
        for (int j = 0; j < 4; ++j) v.push_back(p.matrix()(i, j));
      return v;
    };
  };
  ExpectPoses(ParsePoseFile(Rows("", " ", 1, matrix(3)), "p"));
  ExpectPoses(ParsePoseFile(Rows("", ",", 1, matrix(4)), "p"));
  // Universal Robots: metres and a rotation vector (its RTDE log's names too).
  auto rotvec = [](const Pose& p, const Eigen::Vector3d& t, int) {
    const Eigen::AngleAxisd aa(p.linear());
    const Eigen::Vector3d r = aa.axis() * aa.angle();
    return std::vector<double>{t.x(), t.y(), t.z(), r.x(), r.y(), r.z()};
  };
  ExpectPoses(ParsePoseFile(Rows("x,y,z,rx,ry,rz", ",", 1, rotvec), "p"));
  ExpectPoses(ParsePoseFile(
      Rows("actual_TCP_pose_0 actual_TCP_pose_1 actual_TCP_pose_2 actual_TCP_pose_3 actual_TCP_pose_4 actual_TCP_pose_5",
           " ", 1, rotvec),
      "p"));
  // KUKA: millimetres and A, B, C in degrees, R = Rz(A) Ry(B) Rx(C).
  o = {};
  o.units = PoseUnits::kMillimetres;
  ExpectPoses(ParsePoseFile(Rows("X,Y,Z,A,B,C", ",", 1000, [](const Pose& p, const Eigen::Vector3d& t, int) {
    const Eigen::Vector3d zyx = p.linear().eulerAngles(2, 1, 0) * (180 / M_PI);
    return std::vector<double>{t.x(), t.y(), t.z(), zyx[0], zyx[1], zyx[2]};
  }), "p", o));
  // Fanuc: millimetres and W, P, R in degrees, R = Rz(R) Ry(P) Rx(W).
  ExpectPoses(ParsePoseFile(Rows("X,Y,Z,W,P,R", ",", 1000, [](const Pose& p, const Eigen::Vector3d& t, int) {
    const Eigen::Vector3d zyx = p.linear().eulerAngles(2, 1, 0) * (180 / M_PI);
    return std::vector<double>{t.x(), t.y(), t.z(), zyx[2], zyx[1], zyx[0]};
  }), "p", o));
}

TEST(PoseFile, TimesAreReadInSeconds) {
  EXPECT_EQ(ParsePoseFile("1.5 0 0 0 0 0 0 1\n2.5 0 0 0 0 0 0 1\n", "p").times_s, (std::vector<double>{1.5, 2.5}));  // TUM
  EXPECT_EQ(ParsePoseFile("time [ms],x,y,z,qx,qy,qz,qw\n1500,0,0,0,0,0,0,1\n", "p").times_s, (std::vector<double>{1.5}));
  EXPECT_EQ(ParsePoseFile("timestamp_ns,x,y,z,qx,qy,qz,qw\n1500000000,0,0,0,0,0,0,1\n", "p").times_s,
            (std::vector<double>{1.5}));
  // A date is no time in seconds: the poses go by row.
  EXPECT_TRUE(ParsePoseFile("time,x,y,z,qx,qy,qz,qw\n2026-11-27T05:40:00,0,0,0,0,0,0,1\n", "p").times_s.empty());
  EXPECT_TRUE(ParsePoseFile("frame,x,y,z,qx,qy,qz,qw\n7,0,0,0,0,0,0,1\n", "p").times_s.empty());
  EXPECT_THAT(ErrorOf("time [h],x,y,z,qx,qy,qz,qw\n"), HasSubstr("poses.csv:1: column 1 'time [h]': unknown time unit 'h'"));
}

TEST(PoseFile, MillimetresReadAsMetresAreWarned) {
  auto xyzw = [](const Pose& p, const Eigen::Vector3d& t, int) { return Xyzw(p, t); };
  std::vector<std::string> warnings;
  auto warn = [&](const std::string& w) { warnings.push_back(w); };
  const std::string mm = Rows("x,y,z,qx,qy,qz,qw", ",", 1000, xyzw);
  ParsePoseFile(mm, "poses.csv", {}, warn);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("poses.csv:3: a translation of"));
  EXPECT_THAT(warnings[0], HasSubstr("--pose-units mm"));
  warnings.clear();
  PoseFileOptions o;
  o.units = PoseUnits::kMillimetres;
  ExpectPoses(ParsePoseFile(mm, "poses.csv", o, warn));
  ExpectPoses(ParsePoseFile(Rows("x_mm,y_mm,z_mm,qx,qy,qz,qw", ",", 1000, xyzw), "poses.csv", {}, warn));
  EXPECT_TRUE(warnings.empty());
  o.units = PoseUnits::kMetres;
  EXPECT_THAT(ErrorOf(Rows("x_mm,y_mm,z_mm,qx,qy,qz,qw", ",", 1000, xyzw), o),
              HasSubstr("poses.csv: the header gives translations in mm, the option in m"));
}

TEST(PoseFile, BadInputNamesTheLine) {
  auto xyzw = [](const Pose& p, const Eigen::Vector3d& t, int) { return Xyzw(p, t); };
  // A headerless quaternion row is ambiguous: w first or last?
  EXPECT_THAT(ErrorOf(Rows("", ",", 1, xyzw)), HasSubstr("poses.csv:1: 7 numbers per row"));
  EXPECT_THAT(ErrorOf(Rows("", ",", 1, xyzw)), HasSubstr("--pose-order xyzw or wxyz"));
  EXPECT_THAT(ErrorOf("0,0,0,0,0,0\n"), HasSubstr("poses.csv:1: 6 numbers per row, no header"));
  EXPECT_THAT(ErrorOf("1 2 3 4 5\n"), HasSubstr("poses.csv:1: 5 numbers per row"));
  EXPECT_THAT(ErrorOf("x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,1\n0,0,0,0,0,1\n"), HasSubstr("poses.csv:3: 6 fields, but the first row has 7"));
  EXPECT_THAT(ErrorOf("x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,1\n0,0,abc,0,0,0,1\n"),
              HasSubstr("poses.csv:3: field 3 is not a finite number: \"abc\""));
  EXPECT_THAT(ErrorOf("x;y;z;qx;qy;qz;qw\n0;0;0,5;0;0;0;1\n"),
              HasSubstr("poses.csv:2: field 3 is not a finite number: \"0,5\" (a decimal comma?"));
  EXPECT_THAT(ErrorOf("x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,2\n"), HasSubstr("poses.csv:2: the quaternion must have unit norm"));
  EXPECT_THAT(ErrorOf("x,y,z,qx,qy,qz,qw,elbow\n"), HasSubstr("poses.csv:1: column 8 'elbow': unknown column name"));
  EXPECT_THAT(ErrorOf("x,y,z\n"), HasSubstr("poses.csv:1: header 'x,y,z': no rotation columns"));
  EXPECT_THAT(ErrorOf("x,y,z,qx,qy,qz,qw,a,b,c\n"), HasSubstr("more than one kind of rotation"));
  EXPECT_THAT(ErrorOf("x [in],y,z,qx,qy,qz,qw\n"), HasSubstr("unknown unit 'in'"));
  // Angles in another unit than the form's: no silent factor of 57.
  EXPECT_THAT(ErrorOf("x,y,z,rx [deg],ry [deg],rz [deg]\n"),
              HasSubstr("column 4 'rx [deg]': unit 'deg': rx,ry,rz are a rotation vector in radians"));
  EXPECT_THAT(ErrorOf("x,y,z,a [rad],b [rad],c [rad]\n"), HasSubstr("column 4 'a [rad]': unit 'rad': KUKA's"));
  EXPECT_THAT(ErrorOf("x,y,z,qx [deg],qy,qz,qw\n"), HasSubstr("a quaternion has no unit, got 'deg'"));
  ExpectPoses(ParsePoseFile(Rows("x [m],y [m],z [m],rx [rad],ry [rad],rz [rad]", ",", 1,
                                 [](const Pose& p, const Eigen::Vector3d& t, int) {
                                   const Eigen::AngleAxisd aa(p.linear());
                                   const Eigen::Vector3d r = aa.axis() * aa.angle();
                                   return std::vector<double>{t.x(), t.y(), t.z(), r.x(), r.y(), r.z()};
                                 }),
                            "p"));
  EXPECT_THAT(ErrorOf("1 0 0 0 0 1 0 0 0 0 2 0\n"), HasSubstr("poses.csv:1: not a rotation matrix"));
  EXPECT_THAT(ErrorOf("1 0 0 0 0 1 0 0 0 0 1 0 0 0 1 1\n"), HasSubstr("poses.csv:1: the last row of a 4x4 pose must be 0 0 0 1"));
  EXPECT_THAT(ErrorOf("# nothing\n\n"), HasSubstr("poses.csv: holds no pose"));
  EXPECT_THAT(ErrorOf("x,y,z,qx,qy,qz,qw\n"), HasSubstr("poses.csv: holds no pose"));
}

}  // namespace
}  // namespace lt
