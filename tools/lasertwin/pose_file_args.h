// The options that describe a pose file (--poses FILE), read alike by `scan`
// and `calibrate` (docs/pipeline.md, "Poses from a file").
#pragma once

#include <string>
#include <utility>

#include "core/error.h"
#include "core/text_fields.h"
#include "pipeline/pose_file.h"

namespace lt::cli {

struct PoseFileArgs {
  std::string poses;
  std::string units;              // --pose-units; empty: the header's, else m
  std::string order;              // --pose-order; empty: the header's (headerless 7/8-number rows need it)
  std::string image_time_offset;  // --image-time-offset, seconds; empty: match by time only when the counts differ

  // Throws lt::InputError naming the option: one given without --poses, or a bad value.
  PoseFileOptions Parse() const {
    for (const auto& [option, value] : {std::pair<const char*, const std::string*>{"--pose-units", &units},
                                        {"--pose-order", &order},
                                        {"--image-time-offset", &image_time_offset}}) {
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
    return o;
  }
};

}  // namespace lt::cli
