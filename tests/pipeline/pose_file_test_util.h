// Helpers of the pose file tests (pose_file_test.cpp, pose_file_logs_test.cpp): two test
// poses written in a file's form, and the checks of what is read.
#pragma once

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "core/error.h"
#include "pipeline/pose_file.h"

namespace lt::pose_file_test {

inline Pose TestPose(int k) {
  Pose p = Pose::Identity();
  p.linear() = Eigen::AngleAxisd(0.4 + 0.7 * k, Eigen::Vector3d(0.2, -1, 0.4 + k).normalized()).toRotationMatrix();
  p.translation() = Eigen::Vector3d(0.31 + 0.05 * k, -0.12, 0.5 - 0.02 * k);
  return p;
}

inline std::string Num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Two poses, one row each: `row` writes the numbers of a pose (translation scaled by `scale`).
template <typename Row>
std::string Rows(const std::string& header, const std::string& sep, double scale, Row row) {
  std::string text = header.empty() ? "" : header + "\n";
  for (int k = 0; k < 2; ++k) {
    const Pose p = TestPose(k);
    std::vector<double> v = row(p, Eigen::Vector3d(p.translation() * scale), k);
    for (size_t i = 0; i < v.size(); ++i) text += (i ? sep : "") + Num(v[i]);
    text += "\n";
  }
  return text;
}

inline std::vector<double> Xyzw(const Pose& p, const Eigen::Vector3d& t) {
  const Eigen::Quaterniond q(p.linear());
  return {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
}
inline std::vector<double> Wxyz(const Pose& p, const Eigen::Vector3d& t) {
  const Eigen::Quaterniond q(p.linear());
  return {t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z()};
}

inline void ExpectPoses(const PoseFile& f) {
  ASSERT_EQ(f.poses.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    EXPECT_LT((f.poses[size_t(k)].matrix() - TestPose(k).matrix()).cwiseAbs().maxCoeff(), 1e-12) << f.form << " " << k;
  }
}

inline std::string ErrorOf(const std::string& text, const PoseFileOptions& o = {}) {
  try {
    ParsePoseFile(text, "poses.csv", o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

// Logs as robots, trackers and ROS write them (docs/pipeline.md, "Real logs checked"),
// two poses each: the pose columns read, the columns of other quantities skipped.
inline std::string Log(const std::string& header, const std::function<std::string(const Pose&, int)>& row) {
  std::string text = header + "\n";
  for (int k = 0; k < 2; ++k) text += row(TestPose(k), k) + "\n";
  return text;
}

inline std::string Join(const std::vector<double>& v, const std::string& sep = ",") {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + Num(v[i]);
  return s;
}

}  // namespace lt::pose_file_test
