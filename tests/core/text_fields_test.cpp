// Tests of core/text_fields: the strict number reader and message lists.
#include "core/text_fields.h"

#include <gtest/gtest.h>

namespace lt {
namespace {

TEST(TextFields, ListFirstNamesAllUpToTheLimit) {
  EXPECT_EQ(ListFirst({}, 3), "");
  EXPECT_EQ(ListFirst({"a"}, 3), "a");
  EXPECT_EQ(ListFirst({"a", "b", "c"}, 3), "a, b, c");
}

TEST(TextFields, ListFirstCountsTheRest) {
  EXPECT_EQ(ListFirst({"a", "b", "c", "d"}, 3), "a, b, c and 1 more");
  EXPECT_EQ(ListFirst({"a", "b", "c", "d", "e"}, 1), "a and 4 more");
  EXPECT_EQ(ListFirst({"a", "b", "c"}, 2, '\''), "'a', 'b' and 1 more");
}

TEST(TextFields, ParseFiniteNumberTakesOnlyAWholeFiniteNumber) {
  EXPECT_EQ(ParseFiniteNumber("1"), 1.0);
  EXPECT_EQ(ParseFiniteNumber("+2."), 2.0);
  EXPECT_EQ(ParseFiniteNumber(".5"), 0.5);
  EXPECT_EQ(ParseFiniteNumber("-1e-3"), -1e-3);
  EXPECT_FALSE(ParseFiniteNumber("1x"));
  EXPECT_FALSE(ParseFiniteNumber(""));
  EXPECT_FALSE(ParseFiniteNumber("nan"));
  EXPECT_FALSE(ParseFiniteNumber("inf"));
  EXPECT_FALSE(ParseFiniteNumber("1e999"));
}

}  // namespace
}  // namespace lt
