#include "core/frame_range.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace lt {
namespace {

TEST(FrameRangeTest, ParsesForms) {
  auto r = FrameRange::Parse("2:5");
  EXPECT_EQ(r.Resolve(10), std::make_pair(2, 5));
  EXPECT_EQ(FrameRange::Parse("3").Resolve(10), std::make_pair(3, 4));
  EXPECT_EQ(FrameRange::Parse("4:").Resolve(6), std::make_pair(4, 6));
  EXPECT_EQ(FrameRange::Parse(":2").Resolve(6), std::make_pair(0, 2));
  EXPECT_EQ(FrameRange::Parse(":").Resolve(6), std::make_pair(0, 6));
  EXPECT_EQ(FrameRange::Parse("0:100").Resolve(6), std::make_pair(0, 6));
  EXPECT_THROW(FrameRange::Parse("5:2"), InputError);
  EXPECT_THROW(FrameRange::Parse("3:3"), InputError);
  EXPECT_THROW(FrameRange::Parse("a:2"), InputError);
  EXPECT_THROW(FrameRange::Parse("-1"), InputError);
  EXPECT_THROW(FrameRange::Parse("1:2:3"), InputError);
  EXPECT_THROW(FrameRange::Parse(""), InputError);
  EXPECT_THROW(FrameRange::Parse("7").Resolve(6), InputError);
}

TEST(FrameRangeTest, SaysWhenItAsksForMoreFramesThanThereAre) {
  EXPECT_TRUE(FrameRange::Parse("0:100").Exceeds(6));
  EXPECT_TRUE(FrameRange::Parse("6").Exceeds(6));
  EXPECT_FALSE(FrameRange::Parse("0:6").Exceeds(6));
  EXPECT_FALSE(FrameRange::Parse("4:").Exceeds(6));
  EXPECT_EQ(FrameRange::Parse("4:").EndOrMinusOne(), -1);
  EXPECT_EQ(FrameRange::Parse("4:9").EndOrMinusOne(), 9);
}

TEST(FrameRangeTest, ErrorNamesTheOption) {
  try {
    FrameRange::Parse("x", "--frames");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "--frames");
  }
}

}  // namespace
}  // namespace lt
