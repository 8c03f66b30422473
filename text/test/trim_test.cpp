// cobra::text::trim: the white space around a word, removed on both sides only.
#include "cobra/text/trim.hpp"

#include <gtest/gtest.h>

namespace cobra::text {
namespace {

TEST(Trim, RemovesSpacesTabsAndLineEndsAroundButNotInside) {
  EXPECT_EQ(trim("  a b\t\r\n"), "a b");
  EXPECT_EQ(trim("\tx"), "x");
  EXPECT_EQ(trim("x"), "x");
  EXPECT_EQ(trim("[1, 2] "), "[1, 2]");
}

TEST(Trim, NothingButWhiteSpaceIsEmpty) {
  EXPECT_EQ(trim(""), "");
  EXPECT_EQ(trim(" \t\r\n "), "");
}

}  // namespace
}  // namespace cobra::text
