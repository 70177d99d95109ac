// Stripe points as CSV: header `u,v,width,strength` (plus `,plane` after plane
// identification), one point per line, pixel coordinates in the OpenCV
// convention.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "pipeline/stripe_point.h"

namespace lt {

std::string FormatStripeCsv(const std::vector<StripePoint>& points, bool with_plane);
// Written atomically.
void WriteStripeCsv(const std::filesystem::path& path, const std::vector<StripePoint>& points, bool with_plane);
// Reads either form (plane = -1 without the column). Errors: lt::InputError
// naming "file:line".
std::vector<StripePoint> ReadStripeCsv(const std::filesystem::path& path, bool* with_plane = nullptr);

}  // namespace lt
