// A camera whose pixels are binned n x n, for renders at a fraction of a
// scene's resolution that keep its images' level (calib-session --binning,
// sweep's half-resolution run): the camera's resolution / n, pixel pitch x n,
// fx, fy / n and the principal point moved with the pixel grid, and the image
// sensor as BinnedImageSensor.
#pragma once

#include <nlohmann/json.hpp>

#include "sensor/image_sensor.h"

namespace lt {

// The image sensor of a camera whose pixels are binned n x n, as a real
// camera's binning: a binned pixel sums the charge of n² pixels, so its full
// well is n² times the pixel's and the system gain (DN per e-) n² times
// smaller (the full scale covers the summed well), which keeps the image's
// level: at a given irradiance and exposure the binned pixel's mean DN is the
// pixel's. The sum of n² independent pixels also has n times the dark noise
// (n² reads), n² times the dark current, n times the DSNU and 1/n of the
// PRNU; shot noise in DN is n times smaller (the signal in e- is n² times
// larger). Black level, bit depth, analogue gain, QE and colour filter are
// kept. n = 1 returns `pixel` unchanged.
ImageSensorParams BinnedImageSensor(const ImageSensorParams& pixel, int n);

// Bins a scene's "sensor" section n x n in place: its "camera" (keys it lacks
// or holds in another form are left as they are) and its "image_sensor",
// written from `pixel`, the section's image sensor as parsed (the sensor's
// defaults for keys it leaves out). n = 1 leaves the section unchanged.
void BinSensorSection(nlohmann::json& sensor, const ImageSensorParams& pixel, int n);

}  // namespace lt
