#include "common/parse_number.h"

#include <gtest/gtest.h>

namespace ttz {
namespace {

TEST(ParseNumber, DoubleReadsTheWholeText) {
  EXPECT_EQ(ParseDouble("1.5"), 1.5);
  EXPECT_EQ(ParseDouble("-2e-3"), -2e-3);
  EXPECT_EQ(ParseDouble(" 7"), 7.0);
  EXPECT_FALSE(ParseDouble(""));
  EXPECT_FALSE(ParseDouble("abc"));
  EXPECT_FALSE(ParseDouble("1.5m"));
  EXPECT_FALSE(ParseDouble("1.5 "));
  EXPECT_FALSE(ParseDouble("1e999"));
  EXPECT_FALSE(ParseDouble("1e-310"));  // underflows to a denormal: std::stod says out of range
  EXPECT_FALSE(ParseDouble("nan"));
  EXPECT_FALSE(ParseDouble("-inf"));
}

TEST(ParseNumber, IntReadsTheWholeTextInDecimal) {
  EXPECT_EQ(ParseInt("42"), 42);
  EXPECT_EQ(ParseInt("-3"), -3);
  EXPECT_FALSE(ParseInt("1.5"));
  EXPECT_FALSE(ParseInt("1e3"));
  EXPECT_FALSE(ParseInt(""));
  EXPECT_FALSE(ParseInt("99999999999"));
}

}  // namespace
}  // namespace ttz
