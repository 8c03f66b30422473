// cobra::text::number: printf's %g with a chosen number of significant digits.
#include "cobra/text/number.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace cobra::text {
namespace {

TEST(Number, WritesPrintfsShortestGeneralForm) {
  EXPECT_EQ(number(0.25), "0.25");
  EXPECT_EQ(number(2.0), "2");
  EXPECT_EQ(number(-1e-6), "-1e-06");
  EXPECT_EQ(number(1234567.0), "1.23457e+06");
  EXPECT_EQ(number(0.1 + 0.2), "0.3");
}

TEST(Number, KeepsTheAskedSignificantDigits) {
  EXPECT_EQ(number(0.123456, 3), "0.123");
  EXPECT_EQ(number(1234.5, 3), "1.23e+03");
  EXPECT_EQ(number(1.0 / 3.0, 17), "0.33333333333333331");
}

TEST(Number, NamesNonFiniteValuesAndFitsTheLongestDouble) {
  EXPECT_EQ(number(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(number(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(number(-std::numeric_limits<double>::denorm_min(), 17), "-4.9406564584124654e-324");
}

}  // namespace
}  // namespace cobra::text
