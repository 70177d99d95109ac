// Hostile inputs found reading the YAML and XML readers for the fuzz targets
// (tools/fuzz), minimised: each reader gives a clean lt::InputError naming the
// file and line, never a crash, a stack overflow or gigabytes allocated.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "error_of.h"
#include "pipeline/opencv_yaml.h"
#include "pipeline/yaml_scalar.h"
#include "pipeline/yaml_tree.h"

namespace lt {
namespace {

using ::testing::HasSubstr;

using test::ErrorOf;

std::string Repeat(const std::string& s, int n) {
  std::string out;
  for (int k = 0; k < n; ++k) out += s;
  return out;
}

// Flow collections nested 10 000 deep ("a: [[[[..."), and block mappings each
// indented one more: each level was a recursive call (a stack overflow).
TEST(ReaderFuzz, YamlNestingDeeperThanTheLimitIsAnError) {
  EXPECT_THAT(ErrorOf([] { ParseYamlTree("a: " + Repeat("[", 10000), "t.yaml"); }),
              HasSubstr("t.yaml:1: collections nested deeper than 100 levels"));
  EXPECT_THAT(ErrorOf([] { ParseYamlTree("a: " + Repeat("{b: ", 10000), "t.yaml"); }),
              HasSubstr("t.yaml:1: collections nested deeper than 100 levels"));
  std::string block;
  for (int k = 0; k < 200; ++k) block += std::string(size_t(k), ' ') + "k:\n";
  EXPECT_THAT(ErrorOf([&] { ParseYamlTree(block, "t.yaml"); }),
              HasSubstr("t.yaml:101: collections nested deeper than 100 levels"));
  std::string seq = "a:\n";
  for (int k = 0; k < 200; ++k) seq += std::string(size_t(k), ' ') + "-\n";
  EXPECT_THAT(ErrorOf([&] { ParseYamlTree(seq, "t.yaml"); }), HasSubstr("collections nested deeper than 100 levels"));
  // 100 levels still read.
  const YamlNode root = ParseYamlTree("a: " + Repeat("[", 99) + Repeat("]", 99), "t.yaml");
  EXPECT_EQ(root.Find("a")->kind, YamlNode::Kind::kSeq);
}

// "Billion laughs": nine anchors, each a sequence of ten aliases of the one
// before, made a tree of 10^9 nodes from 300 bytes (gigabytes, then killed).
TEST(ReaderFuzz, YamlAliasesCopyingTooMuchAreAnError) {
  std::string text = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int k = 1; k < 10; ++k) {
    const std::string prev = "*a" + std::to_string(k - 1);
    // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "a" + std::string inlined.
    const std::string n = std::to_string(k);
    text += "a";
    text += n;
    text += ": &a";
    text += n;
    text += " [";
    text += prev;
    for (int j = 1; j < 10; ++j) text += ", " + prev;
    text += "]\n";
  }
  EXPECT_THAT(ErrorOf([&] { ParseYamlTree(text, "t.yaml"); }),
              HasSubstr("the aliases copy more than 1000000 nodes and characters"));
  // Aliases that copy little still read.
  const YamlNode root = ParseYamlTree("a: &m [1, 2, 3]\nb: [*m, *m]\n", "t.yaml");
  ASSERT_EQ(root.Find("b")->seq.size(), 2u);
  EXPECT_EQ(root.Find("b")->seq[1].seq[2].scalar, "3");
}

// The flow collection's scan goes on from where it stopped as lines are
// appended (it rescanned the whole text for every line: 2.0 s for a '[' over
// 20 000 lines, 100 kB; now 0.016 s); what it decides is as before.
TEST(ReaderFuzz, FlowBalanceGoesOnFromWhereItStopped) {
  FlowBalance b;
  char extra = 0;
  std::string s = "[ 1, 'a ] b";
  EXPECT_FALSE(b.Closed(s, &extra));  // the quote is open
  s += " c'";
  EXPECT_FALSE(b.Closed(s, &extra));  // the quote closed, '[' open
  s += ", {x: 2} ]";
  EXPECT_TRUE(b.Closed(s, &extra));
  EXPECT_EQ(extra, 0);
  FlowBalance c;
  EXPECT_FALSE(c.Closed("[ 1 ] ]", &extra));
  EXPECT_EQ(extra, ']');
  // Over lines: a value spanning them, and one never closed (file:line of its key).
  const YamlNode root = ParseYamlTree("a: [ 1,\n  \"x, ]\",\n  3 ]\nb: 2\n", "t.yaml");
  ASSERT_EQ(root.Find("a")->seq.size(), 3u);
  EXPECT_EQ(root.Find("a")->seq[1].scalar, "x, ]");
  // The text of a collection over lines is quoted to its first 80 characters.
  EXPECT_EQ(ErrorOf([] { ParseYamlTree("a: 1\nb: [ 1,\n" + Repeat("  2,\n", 1000) + "  3\n", "t.yaml"); }),
            "t.yaml:2: missing ']' in '[ 1, " + Repeat("2, ", 25) + "...'");
}

// OpenCV XML elements nested 10 000 deep: a recursive call each (a stack overflow).
TEST(ReaderFuzz, XmlNestingDeeperThanTheLimitIsAnError) {
  const std::string text = "<?xml version=\"1.0\"?>\n<opencv_storage>\n" + Repeat("<a>", 10000);
  EXPECT_THAT(ErrorOf([&] { OpenCvYaml::Parse(text, "c.xml"); }),
              HasSubstr("c.xml:3: elements nested deeper than 100 levels"));
}

// Each element's line was counted from the start of the text (quadratic in the
// elements: 2.8 s for 20 000, 358 kB; now 0.025 s); now counted on, and still right.
TEST(ReaderFuzz, XmlLinesAreCountedOn) {
  std::string text = "<?xml version=\"1.0\"?>\n<opencv_storage>\n";
  for (int k = 0; k < 50; ++k) text += "<k" + std::to_string(k) + ">1</k" + std::to_string(k) + ">\n";
  text += "<k7>2</k7>\n</opencv_storage>\n";
  EXPECT_EQ(ErrorOf([&] { OpenCvYaml::Parse(text, "c.xml"); }), "c.xml:53: duplicate key 'k7'");
}

}  // namespace
}  // namespace lt
