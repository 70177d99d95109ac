#include "core/json_reader.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/pose.h"
#include "error_of.h"

namespace lt::json {
namespace {

Document Doc(const std::string& text) { return Document::Parse(text, "scene.json", "/base"); }

using test::ErrorOf;

TEST(JsonReader, RangeErrorNamesFileAndPointer) {
  auto doc = Doc(R"({"sensor": {"camera": {"f_number": 0}}})");
  Object camera = doc.Root().AsObject().GetObject("sensor").GetObject("camera");
  EXPECT_EQ(ErrorOf([&] { camera.Number("f_number", Range::Positive()); }),
            "scene.json: /sensor/camera/f_number: must be > 0, got 0");
}

TEST(JsonReader, UnknownKeyIsAnError) {
  auto doc = Doc(R"({"a": 1, "typo": 2})");
  Object o = doc.Root().AsObject();
  EXPECT_EQ(o.Number("a"), 1.0);
  std::string msg = ErrorOf([&] { o.Finish(); });
  EXPECT_NE(msg.find("scene.json: /typo: unknown key \"typo\""), std::string::npos) << msg;
}

TEST(JsonReader, MissingRequiredKey) {
  auto doc = Doc(R"({"camera": {}})");
  Object cam = doc.Root().AsObject().GetObject("camera");
  EXPECT_EQ(ErrorOf([&] { cam.Number("fx"); }), "scene.json: /camera: missing required key \"fx\"");
}

// A required key written with a typo or without its unit was reported only as
// missing (and the typo as unknown only once the key was there): the message
// names the key the object has instead.
TEST(JsonReader, MissingRequiredKeyNamesItsLikelyMisspelling) {
  auto doc = Doc(R"({"exposre_us": 100, "power_mW": 5, "wavelenght_nm": 650, "power": 1, "fy": 3, "fx": 2, "focus": 1})");
  Object o = doc.Root().AsObject();
  auto missing = [&](const char* key) { return ErrorOf([&] { o.Number(key); }); };
  EXPECT_EQ(missing("exposure_us"),
            "scene.json: /: missing required key \"exposure_us\" (the object has \"exposre_us\": misspelt, or in another unit?)");
  EXPECT_EQ(missing("power_mw"),
            "scene.json: /: missing required key \"power_mw\" (the object has \"power_mW\": misspelt, or in another unit?)");
  EXPECT_EQ(missing("wavelength_nm"),
            "scene.json: /: missing required key \"wavelength_nm\" (the object has \"wavelenght_nm\": misspelt, or in another unit?)");
  EXPECT_EQ(missing("focus_m"), "scene.json: /: missing required key \"focus_m\" (the object has \"focus\": misspelt, or in another unit?)");
  EXPECT_EQ(missing("fz"), "scene.json: /: missing required key \"fz\"");  // short keys: no guess
  EXPECT_EQ(missing("other"), "scene.json: /: missing required key \"other\"");
  // A key some getter asked for is no misspelling.
  auto doc2 = Doc(R"({"gain_db": 1})");
  Object o2 = doc2.Root().AsObject();
  EXPECT_TRUE(o2.Has("gain_db"));
  EXPECT_EQ(ErrorOf([&] { o2.Number("gain_dn"); }), "scene.json: /: missing required key \"gain_dn\"");
}

TEST(JsonReader, WrongTypes) {
  auto doc = Doc(R"({"n": "3", "i": 1.5, "b": 1, "v": [1, 2], "e": "x"})");
  Object o = doc.Root().AsObject();
  EXPECT_EQ(ErrorOf([&] { o.Number("n"); }), "scene.json: /n: must be a number, got a string");
  EXPECT_EQ(ErrorOf([&] { o.Integer("i"); }), "scene.json: /i: must be an integer, got 1.5");
  EXPECT_EQ(ErrorOf([&] { o.Bool("b", false); }), "scene.json: /b: must be true or false, got a number");
  EXPECT_EQ(ErrorOf([&] { o.Vec3("v"); }), "scene.json: /v: must have 3 elements, got 2");
  EXPECT_EQ(ErrorOf([&] { o.Enum("e", {"a", "b"}); }),
            "scene.json: /e: must be one of \"a\", \"b\", got \"x\"");
}

TEST(JsonReader, IntegerWrittenWithAFractionOfZero) {
  auto doc = Doc(R"({"a": 2.0, "b": -3e2, "c": 2.5, "d": 1e300})");
  Object o = doc.Root().AsObject();
  EXPECT_EQ(o.Integer("a"), 2);
  EXPECT_EQ(o.Integer("b"), -300);
  EXPECT_EQ(ErrorOf([&] { o.Integer("c"); }), "scene.json: /c: must be an integer, got 2.5");
  EXPECT_EQ(ErrorOf([&] { o.Integer("d"); }), "scene.json: /d: must be an integer, got 1e+300");
  EXPECT_EQ(ErrorOf([&] { o.Integer("a", Range::AtLeast(3)); }), "scene.json: /a: must be >= 3, got 2");
}

TEST(JsonReader, RepeatedKeyIsAnErrorNamingItsPointer) {
  EXPECT_EQ(ErrorOf([] { Doc(R"({"seed": 1, "seed": 5})"); }),
            "scene.json: /seed: key given twice (JSON leaves a repeated key's meaning open)");
  EXPECT_EQ(ErrorOf([] { Doc(R"({"a": [1, {"x": 0}, [2, 3], {"y": 1, "z": {"k": 1, "k": 2}}]})"); }).rfind(
                "scene.json: /a/3/z/k: key given twice", 0),
            0u);
  // The same key in different objects is fine.
  auto doc = Doc(R"({"a": {"k": 1}, "b": {"k": 2}, "c": [{"k": 3}, {"k": 4}]})");
  EXPECT_EQ(doc.Root().AsObject().GetObject("b").Integer("k"), 2);
}

TEST(JsonReader, NumberOverflowIsAnInputError) {
  EXPECT_EQ(ErrorOf([] { Doc(R"({"x": 1e999})"); }),
            "scene.json: /x: invalid JSON: number overflow parsing '1e999'");
  // The pointer of the value, in objects and arrays (it had none: "scene.json: invalid JSON: ...").
  EXPECT_EQ(ErrorOf([] { Doc(R"({"a": {"b": [1, 2, -1e400]}, "c": 1})"); }),
            "scene.json: /a/b/2: invalid JSON: number overflow parsing '-1e400'");
  EXPECT_EQ(ErrorOf([] { Doc("1e999"); }), "scene.json: invalid JSON: number overflow parsing '1e999'");
}

TEST(JsonReader, SyntaxErrorNamesLineAndColumn) {
  std::string msg = ErrorOf([] { Doc("{\n  \"a\": 1,\n  \"b\": ]\n}"); });
  EXPECT_EQ(msg.rfind("scene.json:3:", 0), 0u) << msg;
  EXPECT_EQ(msg.find("json.exception"), std::string::npos) << msg;
  EXPECT_NE(msg.find("invalid JSON: syntax error"), std::string::npos) << msg;
}

TEST(JsonReader, PointerEscapesAndArrayIndices) {
  auto doc = Doc(R"({"a/b": [{"x~": -1}]})");
  Value x = doc.Root().Child("a/b").Child(size_t(0)).Child("x~");
  EXPECT_EQ(x.pointer(), "/a~1b/0/x~0");
  EXPECT_EQ(ErrorOf([&] { x.Number(Range::NonNegative()); }),
            "scene.json: /a~1b/0/x~0: must be >= 0, got -1");
}

TEST(JsonReader, RelativePathsResolveAgainstFileFolder) {
  auto doc = Doc(R"({"g": "meshes/part.glb", "abs": "/data/x.glb"})");
  Object o = doc.Root().AsObject();
  EXPECT_EQ(o.Path("g"), std::filesystem::path("/base/meshes/part.glb"));
  EXPECT_EQ(o.Path("abs"), std::filesystem::path("/data/x.glb"));
}

TEST(JsonReader, RangeDescriptions) {
  EXPECT_EQ(Range::Closed(0, 1).Describe(), "must be in [0, 1]");
  EXPECT_EQ(Range::ClosedOpen(0, 1).Describe(), "must be in [0, 1)");
  EXPECT_FALSE(Range::Positive().Contains(0.0));
  EXPECT_FALSE(Range::Any().Contains(std::nan("")));
}

TEST(Pose, QuaternionMustBeUnit) {
  auto doc = Doc(R"({"rotation_quat_wxyz": [1, 0.1, 0, 0]})");
  std::string msg = ErrorOf([&] { ReadPose(doc.Root()); });
  EXPECT_NE(msg.find("/rotation_quat_wxyz: rotation quaternion must have unit norm"), std::string::npos)
      << msg;
}

TEST(Pose, RpyAndMatrixAgree) {
  auto a = ReadPose(Doc(R"({"translation_m": [1, 2, 3], "rotation_rpy_deg": [0, 0, 90]})").Root());
  auto b = ReadPose(
      Doc(R"({"translation_m": [1, 2, 3], "rotation_matrix": [[0, -1, 0], [1, 0, 0], [0, 0, 1]]})").Root());
  EXPECT_TRUE(a.isApprox(b, 1e-12));
  EXPECT_TRUE((a * Eigen::Vector3d(1, 0, 0)).isApprox(Eigen::Vector3d(1, 3, 3), 1e-12));
}

TEST(Pose, NonRotationMatrixIsRejected) {
  auto doc = Doc(R"({"rotation_matrix": [[1, 0, 0], [0, 1, 0], [0, 0, -1]]})");
  std::string msg = ErrorOf([&] { ReadPose(doc.Root()); });
  EXPECT_NE(msg.find("determinant -1"), std::string::npos) << msg;
}

TEST(Pose, LookAtFollowsOpenCvAxes) {
  // Camera 1 m above the origin looking straight down, image "up" toward +y.
  auto world_from_cam = ReadPose(
      Doc(R"({"look_at": {"eye_m": [0, 0, 1], "target_m": [0, 0, 0], "up": [0, 1, 0]}})").Root());
  EXPECT_TRUE((world_from_cam.linear().col(2)).isApprox(Eigen::Vector3d(0, 0, -1)));
  EXPECT_TRUE((world_from_cam.linear().col(1)).isApprox(Eigen::Vector3d(0, -1, 0)));  // image down = -up
  EXPECT_NEAR(world_from_cam.linear().determinant(), 1.0, 1e-12);
  auto doc = Doc(R"({"look_at": {"eye_m": [0, 0, 1], "target_m": [0, 0, 0], "up": [0, 0, 1]}})");
  EXPECT_NE(ErrorOf([&] { ReadPose(doc.Root()); }).find("up is parallel"), std::string::npos);
}

TEST(FormatNumber, ShortestRoundTrip) {
  EXPECT_EQ(FormatNumber(0.0), "0");
  EXPECT_EQ(FormatNumber(0.1), "0.1");
  EXPECT_EQ(FormatNumber(1e-9), "1e-09");
  EXPECT_EQ(FormatNumber(10), "10");
  EXPECT_EQ(FormatNumber(-2500), "-2500");
  EXPECT_EQ(FormatNumber(1e20), "1e+20");
  EXPECT_EQ(FormatNumber(1.0 / 3.0), "0.3333333333333333");
}

}  // namespace
}  // namespace lt::json
