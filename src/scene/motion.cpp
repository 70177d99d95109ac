#include "scene/motion.h"

#include <functional>
#include <map>

#include "core/error.h"

namespace lt {

namespace {

StaticMotion ParseStatic(const json::Object& o) {
  StaticMotion m;
  if (auto pose = o.Find("world_from_cam")) m.world_from_cam = ReadPose(*pose);
  return m;
}

// Inline poses: [{"t_s": 0, "world_from_cam": POSE}, ...] (world_from_tool with a
// hand-eye pose), at least two, times strictly increasing.
std::vector<PoseSample> ReadInlinePoses(const json::Value& poses, bool tool_poses) {
  const char* key = tool_poses ? "world_from_tool" : "world_from_cam";
  const char* other = tool_poses ? "world_from_cam" : "world_from_tool";
  std::vector<PoseSample> samples;
  for (const json::Value& item : poses.Array(2)) {
    json::Object e(item);
    if (auto wrong = e.Find(other)) {
      wrong->Fail(tool_poses ? "with \"tool_from_cam\" the poses are the tool's, \"world_from_tool\""
                             : "\"world_from_tool\" poses need the hand-eye pose \"tool_from_cam\" beside \"poses\"");
    }
    json::Value t = e.Get("t_s");
    PoseSample s;
    s.t_s = t.Number();
    if (!samples.empty() && !(s.t_s > samples.back().t_s)) {
      t.Fail("times must strictly increase, got " + FormatNumber(s.t_s) + " after " + FormatNumber(samples.back().t_s));
    }
    const Pose pose = ReadPose(e.Get(key));
    e.Finish();
    s.position = pose.translation();
    s.rotation = Eigen::Quaterniond(pose.linear()).normalized();
    samples.push_back(s);
  }
  return samples;
}

PoseListMotion ParsePoseListMotion(const json::Object& o) {
  PoseListMotion m;
  if (auto pose = o.Find("tool_from_cam")) m.tool_from_cam = ReadPose(*pose);
  m.time_from_first_pose = o.Enum("time_origin", "first_pose", {"first_pose", "file"}) == "first_pose";
  std::optional<json::Value> file = o.Find("file"), poses = o.Find("poses");
  if (file && poses) poses->Fail("give either \"file\" or \"poses\", not both");
  if (poses) {
    if (auto format = o.Find("format")) format->Fail("applies to a pose list \"file\", not to inline \"poses\"");
    m.trajectory = std::make_shared<const PoseTrajectory>(ReadInlinePoses(*poses, m.tool_from_cam.has_value()));
    return m;
  }
  if (!file) o.Fail("missing required key \"file\" (a pose list file) or \"poses\" (the poses inline)");
  m.file = file->ExistingFile("pose list");
  m.format = o.Enum("format", "csv", {"csv", "tum"}) == "csv" ? PoseFileFormat::kCsv : PoseFileFormat::kTum;
  m.trajectory = std::make_shared<const PoseTrajectory>(ReadPoseList(m.file, m.format, m.file.string()));
  return m;
}

using MotionParser = std::function<Motion(const json::Object&)>;

// One entry per motion type: its parser. Adding a type = one line here, one
// alternative in the Motion variant and one overload in the visitors below.
const std::map<std::string, MotionParser>& Parsers() {
  static const std::map<std::string, MotionParser> parsers = {
      {"static", [](const json::Object& o) -> Motion { return ParseStatic(o); }},
      {"pose_list", [](const json::Object& o) -> Motion { return ParsePoseListMotion(o); }},
      {"gcode", [](const json::Object& o) -> Motion { return ParseGcodeMotion(o); }},
  };
  return parsers;
}

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

std::string AbsolutePath(const std::filesystem::path& p) {
  return std::filesystem::absolute(p).lexically_normal().string();
}

}  // namespace

Pose PoseListMotion::WorldFromCam(double time_s) const {
  double t = time_from_first_pose ? time_s + trajectory->StartTime() : time_s;
  Pose world_from = trajectory->At(t);
  return tool_from_cam ? Pose(world_from * *tool_from_cam) : world_from;
}

std::optional<Pose> PoseListMotion::WorldFromTool(double time_s) const {
  if (!tool_from_cam) return std::nullopt;
  return trajectory->At(time_from_first_pose ? time_s + trajectory->StartTime() : time_s);
}

Motion ParseMotion(const json::Value& value) {
  json::Object o(value);
  json::Value type_value = o.Get("type");
  std::string type = type_value.String();
  auto it = Parsers().find(type);
  if (it == Parsers().end()) {
    std::string list;
    for (const auto& [name, parser] : Parsers()) list += (list.empty() ? "\"" : ", \"") + name + "\"";
    type_value.Fail("must be one of " + list + ", got \"" + type + "\"");
  }
  Motion m = it->second(o);
  o.Finish();
  return m;
}

Motion DefaultMotion() { return StaticMotion{}; }

std::string MotionTypeName(const Motion& motion) {
  return std::visit(Overloaded{[](const StaticMotion&) { return std::string("static"); },
                               [](const PoseListMotion&) { return std::string("pose_list"); },
                               [](const GcodeMotion&) { return std::string("gcode"); }},
                    motion);
}

std::vector<std::string> MotionTypeNames() {
  std::vector<std::string> names;
  for (const auto& [name, parser] : Parsers()) names.push_back(name);
  return names;
}

Pose WorldFromCamAt(const Motion& motion, double time_s) {
  return std::visit(Overloaded{[](const StaticMotion& m) { return m.world_from_cam; },
                               [time_s](const PoseListMotion& m) { return m.WorldFromCam(time_s); },
                               [time_s](const GcodeMotion& m) { return m.WorldFromCam(time_s); }},
                    motion);
}

std::optional<Pose> WorldFromToolAt(const Motion& motion, double time_s) {
  if (const auto* m = std::get_if<PoseListMotion>(&motion)) return m->WorldFromTool(time_s);
  if (const auto* m = std::get_if<GcodeMotion>(&motion)) return m->WorldFromTool(time_s);
  return std::nullopt;
}

nlohmann::json MotionToJson(const Motion& motion) {
  return std::visit(
      Overloaded{[](const StaticMotion& m) {
                   return nlohmann::json{{"type", "static"}, {"world_from_cam", PoseToJson(m.world_from_cam)}};
                 },
                 [](const PoseListMotion& m) {
                   nlohmann::json j{{"type", "pose_list"},
                                    {"time_origin", m.time_from_first_pose ? "first_pose" : "file"}};
                   if (m.file.empty()) {
                     const char* key = m.tool_from_cam ? "world_from_tool" : "world_from_cam";
                     nlohmann::json poses = nlohmann::json::array();
                     for (const PoseSample& s : m.trajectory->samples()) {
                       Pose pose = Pose::Identity();
                       pose.linear() = s.rotation.toRotationMatrix();
                       pose.translation() = s.position;
                       poses.push_back({{"t_s", s.t_s}, {key, PoseToJson(pose)}});
                     }
                     j["poses"] = poses;
                   } else {
                     j["file"] = AbsolutePath(m.file);
                     j["format"] = PoseFileFormatName(m.format);
                   }
                   if (m.tool_from_cam) j["tool_from_cam"] = PoseToJson(*m.tool_from_cam);
                   return j;
                 },
                 [](const GcodeMotion& m) { return GcodeMotionToJson(m); }},
      motion);
}

std::vector<std::string> MotionNotes(const Motion& motion) {
  if (const auto* g = std::get_if<GcodeMotion>(&motion)) return GcodeMotionNotes(*g);
  return {};
}

}  // namespace lt
