// Output files of `lasertwin scan` (docs/pipeline.md, "Outputs"):
//
// centers/NNNNNN.csv, one per laser frame, header
//   u,v,width,strength,plane,x_cam,y_cam,z_cam,x_world,y_world,z_world
// one line per extracted stripe point: u, v, width, strength as `lasertwin
// extract` writes them (pixels, image units), plane the global laser plane
// number (-1: not identified), then the triangulated point in the camera frame
// and in the world frame, metres. A point without a 3D position (no plane,
// rejected ray) has the x_cam..z_world fields empty; a frame without a known
// pose has the world fields empty. No field is ever NaN or infinite.
//
// cloud.ply: binary little-endian PLY, one vertex per triangulated point:
//   property double x, y, z     metres, world frame (camera frame when some
//                               frame has no pose; the header comment says which)
//   property int frame          frame index
//   property int plane          global laser plane number
//   property int label          only when the run has ground truth: the instance
//                               id (gt/ "instance") at the point's pixel, -1 for
//                               none
//   property uchar red, green, blue   only when the cloud has colour (from the
//                               bright frames, pipeline/colorize.h; 0 0 0 for a
//                               point no bright frame sees)
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "pipeline/triangulation.h"

namespace lt {

std::string FormatScanCsv(const std::vector<ScanPoint>& points);
void WriteScanCsv(const std::filesystem::path& path, const std::vector<ScanPoint>& points);  // atomic
// Reads a file written by WriteScanCsv; errors are lt::InputError naming "file:line".
std::vector<ScanPoint> ReadScanCsv(const std::filesystem::path& path);

struct CloudPoint {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  int frame = 0;
  int plane = 0;
  std::array<uint8_t, 3> rgb = {0, 0, 0};  // used when the cloud has colour
  int label = -1;                          // used when the cloud has labels
};

struct PointCloud {
  std::vector<CloudPoint> points;
  bool has_colour = false;
  bool has_label = false;
  bool world_frame = true;  // false: camera frame
};

// The PLY file's bytes. Throws std::invalid_argument on a non-finite coordinate.
std::string FormatPly(const PointCloud& cloud);
void WritePly(const std::filesystem::path& path, const PointCloud& cloud);  // atomic
// Reads a file FormatPly wrote (any of its property sets); errors are
// lt::InputError naming the file.
PointCloud ReadPly(const std::filesystem::path& path);

}  // namespace lt
