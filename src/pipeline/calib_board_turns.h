// Symmetric checkerboards (rows + cols even, pipeline/calib_checkerboard.h):
// the turns of the board frame that map the board onto itself, and one board
// frame for every view of a hand-eye calibration, chosen from the robot's
// motion (docs/calibration.md, "Symmetric boards").
#pragma once

#include <string>
#include <vector>

#include "core/pose.h"
#include "pipeline/calib_checkerboard.h"
#include "pipeline/calib_hand_eye.h"

namespace lt {

// The board-frame transforms G that map the board onto itself, turns about its
// normal through its centre: the identity; a half turn when Symmetric(); the
// two quarter turns too when rows == cols. A detected corner at p (the frame
// the detector chose) is at G·p in a turned frame.
std::vector<Pose> BoardTurns(const CheckerboardSpec& board);

// Gives every observation the board frame of the first. For view j and each
// turn G, the camera's motion from view 0, B = cam_from_target_0 ·
// (cam_from_target_j · G⁻¹)⁻¹, must turn by the same angle as the tool's,
// A = base_from_tool_0⁻¹ · base_from_tool_j (AX = XB); the turn whose angle
// matches best is taken when every other misses by at least 3 times as much
// and by 1°: cam_from_target becomes cam_from_target · G⁻¹ and the target
// points G·p (the pixels stay). Returns per observation "" when kept, else why
// it is not (no turn stands out: the motion's angle is the same for two).
std::vector<std::string> AlignBoardFrames(const CheckerboardSpec& board,
                                          std::vector<HandEyeObservation>* observations);

}  // namespace lt
