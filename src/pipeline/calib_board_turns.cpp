#include "pipeline/calib_board_turns.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "pipeline/calib_geometry.h"
#include "pipeline/option_checks.h"

namespace lt {

std::vector<Pose> BoardTurns(const CheckerboardSpec& board) {
  const Eigen::Vector3d centre(0.5 * (board.cols - 1) * board.square_m, 0.5 * (board.rows - 1) * board.square_m, 0);
  std::vector<double> angles = {0};
  if (board.Symmetric()) angles.push_back(M_PI);
  if (board.Symmetric() && board.rows == board.cols) angles.insert(angles.end(), {0.5 * M_PI, -0.5 * M_PI});
  std::vector<Pose> turns;
  for (double a : angles) {
    Pose g = Pose::Identity();
    g.linear() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    g.translation() = centre - g.linear() * centre;
    turns.push_back(g);
  }
  return turns;
}

std::vector<std::string> AlignBoardFrames(const CheckerboardSpec& board,
                                          std::vector<HandEyeObservation>* observations) {
  std::vector<std::string> why(observations->size());
  const std::vector<Pose> turns = BoardTurns(board);
  if (turns.size() < 2 || observations->size() < 2) return why;
  constexpr double kDeg = M_PI / 180.0;
  const HandEyeObservation& first = observations->front();
  for (size_t j = 1; j < observations->size(); ++j) {
    HandEyeObservation& o = (*observations)[j];
    const double tool_angle = RotationAngle((first.base_from_tool.inverse() * o.base_from_tool).linear());
    std::vector<std::pair<double, size_t>> miss;  // |angle(A) - angle(B)|, turn
    for (size_t k = 0; k < turns.size(); ++k) {
      const Pose cam_motion = first.cam_from_target * (o.cam_from_target * turns[k].inverse()).inverse();
      miss.push_back({std::abs(RotationAngle(cam_motion.linear()) - tool_angle), k});
    }
    std::sort(miss.begin(), miss.end());
    if (!(miss[1].first >= std::max(3 * miss[0].first, 1.0 * kDeg))) {
      why[j] = "the board is symmetric and the tool's turn from the first view (" + Fmt(tool_angle / kDeg, 3) +
               " deg) does not tell its frame: two turns of the board match it within " +
               Fmt(miss[0].first / kDeg, 2) + " and " + Fmt(miss[1].first / kDeg, 2) + " deg";
      continue;
    }
    const Pose& g = turns[miss[0].second];
    o.cam_from_target = o.cam_from_target * g.inverse();
    for (Eigen::Vector3d& p : o.target_points) p = g * p;
  }
  return why;
}

}  // namespace lt
