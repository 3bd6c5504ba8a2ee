#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

#include "odometry/types/stamp.h"

namespace uf {
namespace {

TEST(StampTest, ParsesDecimalSecondsExactly) {
  EXPECT_EQ(ParseSeconds("1305031102.160407"), Stamp{1305031102160407000});
  EXPECT_EQ(ParseSeconds("1403636579.763555584"), Stamp{1403636579763555584});  // EuRoC, all 19 digits
  EXPECT_EQ(ParseSeconds("0"), Stamp{0});
  EXPECT_EQ(ParseSeconds("+1.5"), Stamp{1500000000});
  EXPECT_EQ(ParseSeconds("1."), Stamp{1000000000});
  EXPECT_EQ(ParseSeconds(".25"), Stamp{250000000});
}

TEST(StampTest, ParsesScientificNotation) {
  EXPECT_EQ(ParseSeconds("1.037359e-01"), Stamp{103735900});  // KITTI times.txt
  EXPECT_EQ(ParseSeconds("1.5E+2"), Stamp{150000000000});
  EXPECT_EQ(ParseSeconds("1e-9"), Stamp{1});
}

TEST(StampTest, RoundsHalfAwayFromZero) {
  EXPECT_EQ(ParseSeconds("0.0000000015"), Stamp{2});
  EXPECT_EQ(ParseSeconds("0.0000000014999"), Stamp{1});
  EXPECT_EQ(ParseSeconds("5e-10"), Stamp{1});
  EXPECT_EQ(ParseSeconds("-5e-10"), Stamp{-1});
  EXPECT_EQ(ParseSeconds("-0.0000000025"), Stamp{-3});
}

TEST(StampTest, ParsesNegativeSeconds) {
  EXPECT_EQ(ParseSeconds("-0.5"), Stamp{-500000000});
  EXPECT_EQ(ParseSeconds("-12.000000001"), Stamp{-12000000001});
}

TEST(StampTest, RejectsWhatIsNotAFiniteNumberInRange) {
  for (const char* text : {"", "abc", "1e", "1e+", "nan", "inf", "-inf", ".", "-", "1.2.3", " 1", "1 ", "1x",
                           "0x10", "1e30", "-1e30", "9223372037"}) {
    EXPECT_FALSE(ParseSeconds(text).has_value()) << '"' << text << '"';
  }
}

TEST(StampTest, FormatsNineDecimals) {
  EXPECT_EQ(FormatSeconds(0), "0.000000000");
  EXPECT_EQ(FormatSeconds(-1), "-0.000000001");
  EXPECT_EQ(FormatSeconds(1305031102160407000), "1305031102.160407000");
  EXPECT_EQ(FormatSeconds(-1500000000), "-1.500000000");
}

TEST(StampTest, FormatThenParseRoundTrips) {
  for (Stamp t : {Stamp{0}, Stamp{1}, Stamp{-1}, Stamp{999999999}, Stamp{1000000000},
                  Stamp{-1403636579763555584}, Stamp{1403636579763555584}, std::numeric_limits<Stamp>::max(),
                  std::numeric_limits<Stamp>::min() + 1}) {
    EXPECT_EQ(ParseSeconds(FormatSeconds(t)), t) << FormatSeconds(t);
  }
}

TEST(StampTest, ConvertsToAndFromDoubleSeconds) {
  EXPECT_EQ(FromSeconds(1.5), Stamp{1500000000});
  EXPECT_EQ(FromSeconds(-2.0000000004), Stamp{-2000000000});
  EXPECT_DOUBLE_EQ(ToSeconds(2500000000), 2.5);
}

}  // namespace
}  // namespace uf
