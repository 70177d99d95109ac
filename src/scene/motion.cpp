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

using MotionParser = std::function<Motion(const json::Object&)>;

// One entry per motion type: its parser. Adding a type = one line here, one
// alternative in the Motion variant and one overload in the visitors below.
const std::map<std::string, MotionParser>& Parsers() {
  static const std::map<std::string, MotionParser> parsers = {
      {"static", [](const json::Object& o) -> Motion { return ParseStatic(o); }},
  };
  return parsers;
}

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

}  // namespace

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
  return std::visit(Overloaded{[](const StaticMotion&) { return std::string("static"); }}, motion);
}

std::vector<std::string> MotionTypeNames() {
  std::vector<std::string> names;
  for (const auto& [name, parser] : Parsers()) names.push_back(name);
  return names;
}

Pose WorldFromCamAt(const Motion& motion, double /*time_s*/) {
  return std::visit(Overloaded{[](const StaticMotion& m) { return m.world_from_cam; }}, motion);
}

nlohmann::json MotionToJson(const Motion& motion) {
  return std::visit(Overloaded{[](const StaticMotion& m) {
                      return nlohmann::json{{"type", "static"}, {"world_from_cam", PoseToJson(m.world_from_cam)}};
                    }},
                    motion);
}

}  // namespace lt
