// Base64 against the test vectors of RFC 4648, section 10.
#include <gtest/gtest.h>

#include <string>

#include "core/base64.h"

namespace lt {
namespace {

std::string Encode(const std::string& s) { return Base64Encode(reinterpret_cast<const uint8_t*>(s.data()), s.size()); }

TEST(Base64, Rfc4648Vectors) {
  EXPECT_EQ(Encode(""), "");
  EXPECT_EQ(Encode("f"), "Zg==");
  EXPECT_EQ(Encode("fo"), "Zm8=");
  EXPECT_EQ(Encode("foo"), "Zm9v");
  EXPECT_EQ(Encode("foob"), "Zm9vYg==");
  EXPECT_EQ(Encode("fooba"), "Zm9vYmE=");
  EXPECT_EQ(Encode("foobar"), "Zm9vYmFy");
  const uint8_t high[] = {0xff, 0xfe, 0x00};
  EXPECT_EQ(Base64Encode(high, 3), "//4A");
}

}  // namespace
}  // namespace lt
