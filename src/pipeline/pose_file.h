// Per-frame poses from the file a robot controller, a printer or a tracking
// tool writes (`lasertwin scan --poses FILE`, docs/pipeline.md, "Poses from a
// file"): one pose per frame, in frame order. Forms, one per file:
//   CSV with a header naming the columns (',' ';' or tab separated, any order):
//     translation x y z (also tx.., pos_x.., x_m, x_mm, "x [mm]": a unit in the
//     name sets the units), and one rotation:
//       qx qy qz qw          unit quaternion (also q_x.., quat_x..)
//       q1 q2 q3 q4          ABB's quaternion, w first
//       rx ry rz             rotation vector in radians (Universal Robots)
//       a b c                KUKA's angles in degrees, R = Rz(a) Ry(b) Rx(c)
//       w p r                Fanuc's angles in degrees, R = Rz(r) Ry(p) Rx(w)
//     names of several words: EuRoC's p_RS_R_x, q_RS_w; ROS's (rostopic echo -p)
//     field.pose.position.x, field.pose.orientation.w, field.transform.rotation.w;
//     a time: t, time, timestamp, stamp (seconds, or the unit in brackets: s,
//     ms, us, ns), t_s, time_s, timestamp_s, t_ns, time_ns, timestamp_ns; ROS's
//     field.header.stamp (ns) before its %time (ns); PlotJuggler's
//     /topic/header/stamp (s, or ns from 1e17); a stamp in two columns, seconds and nanoseconds
//     (ROS 2's header.stamp.sec + header.stamp.nanosec, ROS 1's secs + nsecs,
//     stamp_sec + stamp_nsec; one part of a stamp alone is an error, time_sec or
//     timestamp_nsec alone a time), before a time of one column; a time without a
//     unit >= 1e17 is in ns (EuRoC's #timestamp);
//     columns named frame, index, image, file, filename, id or name are skipped,
//     and those of other quantities: velocities, biases, covariances, twists,
//     ROS's header.seq and frame_id (its child_frame_id names the body: rows of
//     several child frames need options.body, which keeps that one's rows), ABB's cf1 cf4 cf6 cfx, move_type, speed,
//     zone, PlotJuggler's roll_deg, pitch_deg, yaw_deg beside the quaternion they
//     derive from. In a UR RTDE log every field but actual_TCP_pose_0..5 is skipped
//     (target_TCP_pose too, read when it is the only pose: a planned path); in a
//     KUKA RSI log every field but its actual pose X_RIst..C_RIst (mm, degrees);
//     in a Franka log every field but its O_T_EE (O_T_EE[0..15], field.O_T_EE0..15:
//     a 4x4 matrix column-major, m; a log of its commanded pose only is refused).
//     Any other name is an error: it may be a second pose (x2, pose_b_x), or a
//     tool, work object or external axis changing the pose's frame.
//     OptiTrack Motive's CSV export (settings, Type, Name, ID, Rotation/Position
//     rows above Frame,Time,X,Y,Z,W,X,Y,Z): its rigid body's quaternion and
//     position (of several, the one options.body names), in its length unit
//     (pose_file_motive.h); Vicon Nexus exports
//     (several header rows, angles in degrees), Qualisys QTM TSV exports (Euler
//     angles of a definition the file does not give) and JSON files (nerfstudio's
//     OpenGL camera axes) are refused. Fields may be double-quoted; a separator
//     inside quotes or brackets ("covariance[0;1]") separates nothing.
//   rows of numbers without a header:
//     7  x y z + quaternion: its order (w first or last) must be given (order)
//     8  blank separated: TUM (timestamp tx ty tz qx qy qz qw); comma separated:
//        a time or index, then 7 as above (order needed)
//     12 a 3x4 matrix [R | t], row-major (KITTI's poses)
//     16 a 4x4 matrix, row-major, last row 0 0 0 1
// Blank lines and lines starting with '#' are skipped (a UTF-8 BOM too).
// Units: metres, unless the options or a header say millimetres; translations
// above 5 m are warned about as probably millimetres. Rotations must be
// rotations (quaternion norm 1 to 1e-3, matrix orthonormal to 1e-4), then are
// re-normalised; a rotation vector longer than 2 pi (degrees?) is an error.
// Errors are lt::InputError naming "FILE:LINE".
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/pose.h"

namespace lt {

enum class QuaternionOrder { kXyzw, kWxyz };
enum class PoseUnits { kMetres, kMillimetres };

struct PoseFileOptions {
  std::optional<PoseUnits> units;         // unset: the header's, else metres
  std::optional<QuaternionOrder> order;   // headerless 7/8-column rows need it (not TUM)
  // Matching (scan_poses.h): seconds added to every image name's time before
  // its pose is interpolated; set, the poses must be matched by time.
  std::optional<double> image_time_offset_s;
  // --pose-body: the body whose poses are read from a file of several: an OptiTrack
  // Motive export's rigid body by its name, or the rows whose child_frame_id (ROS's tf,
  // Odometry) is this. Unset: a file of several bodies is an error naming them.
  std::optional<std::string> body;
};

struct PoseFile {
  std::vector<Pose> poses;          // in metres, in file order
  std::vector<int> lines;           // the line of each pose
  std::vector<double> times_s;      // the time of each pose (TUM, a time column), seconds; empty without
  std::string form;                 // e.g. "CSV columns x,y,z,qx,qy,qz,qw", "TUM", "3x4 matrices"
  PoseUnits units = PoseUnits::kMetres;
};

// Reads a pose file. Warnings (millimetre-sized translations read as metres) go to `warn`.
PoseFile ReadPoseFile(const std::filesystem::path& path, const PoseFileOptions& options = {},
                      const std::function<void(const std::string&)>& warn = {});
// The same on text; errors name display_name.
PoseFile ParsePoseFile(const std::string& text, const std::string& display_name, const PoseFileOptions& options = {},
                       const std::function<void(const std::string&)>& warn = {});

// "xyzw" | "wxyz"; "m" | "mm". Throw lt::InputError naming `option`.
QuaternionOrder ParseQuaternionOrder(const std::string& text, const std::string& option);
PoseUnits ParsePoseUnits(const std::string& text, const std::string& option);

}  // namespace lt
