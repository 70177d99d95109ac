// The YAML tree (pipeline/yaml_tree.h), the one reader of every YAML file:
// what it reads beyond block and flow collections (block scalars, anchors and
// aliases, a value on the line after its key) and its errors at file:line;
// OpenCV's FileStorage subset (pipeline/opencv_yaml.h) read from it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/error.h"
#include "pipeline/opencv_yaml.h"
#include "pipeline/yaml_tree.h"

namespace lt {
namespace {

using ::testing::HasSubstr;

// The error of parsing `text`: "where: message".
std::string ErrorOf(const std::string& text) {
  try {
    ParseYamlTree(text, "t.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

// Literal and folded block scalars with their chomping indicators, comments
// and blank lines inside them kept as text. (Before: refused, "block scalars
// (| or >) are not supported".)
TEST(YamlTree, BlockScalars) {
  const YamlNode root = ParseYamlTree(
      "a: |\n  one # not a comment\n\n   two\nb: >-\n  folded\n  line\n\n  next\n    kept\n  end\n"
      "c: |+\n  keep\n\n\nd: |2-\n    indented\ne: 1\n",
      "t.yaml");
  ASSERT_EQ(root.map.size(), 5u);
  EXPECT_EQ(root.Find("a")->scalar, "one # not a comment\n\n two\n");
  EXPECT_TRUE(root.Find("a")->quoted);  // a string, never a number
  EXPECT_EQ(root.Find("a")->line, 1);
  EXPECT_EQ(root.Find("b")->scalar, "folded line\nnext\n  kept\nend");
  EXPECT_EQ(root.Find("c")->scalar, "keep\n\n\n");
  EXPECT_EQ(root.Find("d")->scalar, "  indented");
  EXPECT_EQ(root.Find("e")->scalar, "1");
  EXPECT_EQ(root.Find("e")->line, 18);
  EXPECT_EQ(ErrorOf("a: |x\n  text\n"), "t.yaml:1: unexpected text after the block scalar's '|': 'x'");
  EXPECT_EQ(ErrorOf("a: |\n    first\n  less\n"),
            "t.yaml:3: a line of the block scalar 'a' indented less than its first line");
}

// Anchors and aliases, in block and flow collections. (Before: refused,
// "anchors and aliases are not supported".)
TEST(YamlTree, AnchorsAndAliases) {
  const YamlNode root = ParseYamlTree(
      "base: &b\n  rows: 3\n  data: [&x 1.5, *x, !!str &y 2, *y]\ncopy: *b\n"
      "tagged: &m !!opencv-matrix\n  rows: 1\nagain: *m\n",
      "t.yaml");
  const YamlNode* copy = root.Find("copy");
  ASSERT_NE(copy, nullptr);
  EXPECT_EQ(copy->line, 4);
  EXPECT_EQ(copy->Find("rows")->scalar, "3");
  ASSERT_EQ(copy->Find("data")->seq.size(), 4u);
  EXPECT_EQ(copy->Find("data")->seq[1].scalar, "1.5");
  EXPECT_EQ(copy->Find("data")->seq[3].scalar, "2");
  EXPECT_EQ(copy->Find("data")->seq[3].tag, "!!str");
  EXPECT_EQ(root.Find("again")->tag, "!!opencv-matrix");
  EXPECT_EQ(ErrorOf("a: *none\n"), "t.yaml:1: unknown alias '*none' (its anchor '&none' must come before it)");
  EXPECT_EQ(ErrorOf("a: &x 1\nb: *x x\n"), "t.yaml:2: unexpected text after the alias: 'x'");
}

// A value may start on the line after its key, more indented. (Before:
// "expected 'key: value'".)
TEST(YamlTree, ValueOnTheNextLine) {
  const YamlNode root = ParseYamlTree("data:\n   [ 1, 2,\n     3 ]\nname:\n  \"quoted\"\n", "t.yaml");
  ASSERT_EQ(root.Find("data")->seq.size(), 3u);
  EXPECT_EQ(root.Find("data")->seq[2].scalar, "3");
  EXPECT_EQ(root.Find("name")->scalar, "quoted");
  EXPECT_TRUE(root.Find("name")->quoted);
}

// The first line, for a caller that requires a header (OpenCV's "%YAML:1.0"),
// and the errors of an unclosed flow collection and a top-level sequence.
TEST(YamlTree, FirstLineAndErrors) {
  YamlLine first;
  ParseYamlTree("\xEF\xBB\xBF# comment\r\n\r\n%YAML:1.0\r\n---\r\na: 1\r\n", "t.yaml", &first);
  EXPECT_EQ(first.no, 3);
  EXPECT_EQ(first.text, "%YAML:1.0");
  ParseYamlTree("", "t.yaml", &first);
  EXPECT_EQ(first.no, 1);
  EXPECT_EQ(first.text, "");
  EXPECT_EQ(ErrorOf("a: [ 1, 2\n"), "t.yaml:1: missing ']' in '[ 1, 2'");
  EXPECT_THAT(ErrorOf("- 1\n"), HasSubstr("t.yaml:1: top-level sequences are not supported"));
}

// OpenCV's FileStorage YAML read from the tree: what its own parser refused
// before ("quoted keys are not supported", "top-level sequences are not
// supported" for a sequence at its key's indentation or a second document,
// "'!!opencv-matrix' must be followed by its indented block" for a flow
// matrix, "data must be a sequence [ v0, v1, ... ]" for a block sequence,
// "not an OpenCV FileStorage YAML file" after a BOM) now reads as the tree
// reads it; what it skipped (block scalars, anchors) are values.
TEST(OpenCvYaml, ReadsWhatTheTreeReads) {
  const OpenCvYaml y = OpenCvYaml::Parse(
      "\xEF\xBB\xBF%YAML:1.0\r\n---\r\n\"image width\": 640\r\nnote: |\r\n  two\r\n  lines\r\n"
      "base: &b 12\r\ncopy: *b\r\n"
      "list:\r\n- 1\r\n- 2\r\nflow: !!opencv-matrix { rows: 1, cols: 2, dt: d, data: [ 1., 2. ] }\r\n"
      "block: !!opencv-matrix\r\n   rows: 2\r\n   cols: 1\r\n   dt: d\r\n   data:\r\n   - 3.\r\n   - 4.\r\n"
      "---\r\nsecond: document\r\n",
      "x.yml");
  std::vector<std::string> keys;
  for (const YamlEntry& e : y.entries()) keys.push_back(e.key);
  EXPECT_EQ(keys, (std::vector<std::string>{"image width", "note", "base", "copy", "list", "flow", "block"}));
  EXPECT_EQ(y.Integer(*y.Find("image width"), 1, 10000), 640);
  EXPECT_EQ(y.String(*y.Find("note")), "two\nlines\n");
  EXPECT_THROW(y.Number(*y.Find("note")), InputError);
  EXPECT_EQ(y.Integer(*y.Find("copy"), 0, 100), 12);
  EXPECT_EQ(y.Find("copy")->line, 8);
  EXPECT_EQ(y.Find("list")->kind, YamlEntry::Kind::kOther);
  EXPECT_EQ(y.Matrix(*y.Find("flow")).data, (std::vector<double>{1, 2}));
  EXPECT_EQ(y.Matrix(*y.Find("block")).data, (std::vector<double>{3, 4}));
  EXPECT_EQ(y.Matrix(*y.Find("block")).rows, 2);
  // A line in a matrix that is no key names the matrix.
  try {
    OpenCvYaml::Parse("%YAML:1.0\nm: !!opencv-matrix\n   rows: 1\n   just text\n", "x.yml");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "x.yml:4: expected 'key: value' in 'm', got 'just text'");
  }
}

// A caller that has the tree (ReadCalibrationFile, which tries other tools'
// formats on it first) reads the same entries from it as from the text.
TEST(OpenCvYaml, ReadsFromAParsedTree) {
  const std::string text = "%YAML:1.0\n---\nw: 640\nm: !!opencv-matrix\n   rows: 1\n   cols: 2\n   dt: d\n"
                           "   data: [ 1., 2. ]\n";
  YamlLine first;
  const YamlNode root = ParseYamlTree(text, "x.yml", &first);
  const OpenCvYaml y = OpenCvYaml::Parse(root, first, "x.yml");
  ASSERT_EQ(y.entries().size(), 2u);
  EXPECT_EQ(y.Integer(*y.Find("w"), 1, 10000), 640);
  EXPECT_EQ(y.Where(*y.Find("m")), "x.yml:4");
  EXPECT_EQ(y.Matrix(*y.Find("m")).data, (std::vector<double>{1, 2}));
  // Without the %YAML directive the tree is no OpenCV file, as the text is not.
  const YamlNode plain = ParseYamlTree("w: 640\n", "p.yml", &first);
  try {
    OpenCvYaml::Parse(plain, first, "p.yml");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()), ::testing::StartsWith("p.yml:1: not an OpenCV FileStorage YAML file"));
  }
}

}  // namespace
}  // namespace lt
