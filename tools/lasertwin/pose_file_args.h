// The options that describe a pose file (--poses FILE), read alike by `scan`
// and `calibrate` (docs/pipeline.md, "Poses from a file").
#pragma once

#include <string>
#include <utility>

#include "core/error.h"
#include "core/text_fields.h"
#include "pipeline/pose_file.h"
#include "tools/lasertwin/command.h"

namespace lt::cli {

struct PoseFileArgs {
  std::string poses;
  std::string units;              // --pose-units; empty: the header's, else m
  std::string order;              // --pose-order; empty: the header's (headerless 7/8-number rows need it)
  std::string image_time_offset;  // --image-time-offset, seconds; empty: match by time only when the counts differ
  std::string body;               // --pose-body; empty: the file's one body

  // Declares --poses (described by `poses_help`, what the command takes the poses
  // for) and the options that describe the file.
  void Declare(CLI::App* cmd, const std::string& poses_help) {
    cmd->add_option("--poses", poses, poses_help);
    cmd->add_option("--pose-units", units, "m | mm: the pose file's translations (default: its header's, else m)");
    cmd->add_option("--pose-order", order,
                    "xyzw | wxyz: the quaternion order of a pose file without a header (TUM's is xyzw)");
    cmd->add_option("--image-time-offset", image_time_offset,
                    "Seconds added to each image name's time before its pose is interpolated (a camera stamping the "
                    "start of its exposure: half the exposure; a camera clock behind the robot's: the lag); matches "
                    "every frame by time");
    cmd->add_option("--pose-body", body,
                    "NAME: the body whose poses are read from a pose file of several: an OptiTrack Motive export's "
                    "rigid body, or the rows of one child_frame_id (a ROS tf or Odometry CSV); needed when the file "
                    "holds several");
  }

  // Throws lt::InputError naming the option: one given without --poses, or a bad value.
  PoseFileOptions Parse() const {
    for (const auto& [option, value] : {std::pair<const char*, const std::string*>{"--pose-units", &units},
                                        {"--pose-order", &order},
                                        {"--image-time-offset", &image_time_offset},
                                        {"--pose-body", &body}}) {
      if (poses.empty() && !value->empty()) throw InputError(option, "describes a pose file: give it with --poses");
    }
    PoseFileOptions o;
    if (!image_time_offset.empty()) {
      o.image_time_offset_s = ParseFiniteNumber(image_time_offset);
      if (!o.image_time_offset_s) {
        throw InputError("--image-time-offset", "'" + image_time_offset + "' is not a number of seconds");
      }
    }
    if (!units.empty()) o.units = ParsePoseUnits(units, "--pose-units");
    if (!order.empty()) o.order = ParseQuaternionOrder(order, "--pose-order");
    if (!body.empty()) o.body = body;
    return o;
  }
};

}  // namespace lt::cli
