#include "m2mlat/report/table.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "m2mlat/core/error.hpp"

using namespace m2mlat;

TEST(Table, AlignsTextLeftAndNumbersRight) {
  report::Table t({"scenario", "median"});
  t.add_row({"static_wifi", "874.5"});
  t.add_row({"5g", "1030.0"});
  EXPECT_EQ(t.render(),
            "scenario     median\n"
            "-------------------\n"
            "static_wifi   874.5\n"
            "5g           1030.0\n");
  EXPECT_THROW(t.add_row({"only one"}), core::Error);
}

TEST(Table, NumberText) {
  EXPECT_EQ(report::ms_text(874.4999, 1), "874.5");
  EXPECT_EQ(report::ms_text(std::nan(""), 1), "-");
  EXPECT_EQ(report::percent_text(0.1364, 1), "13.6 %");
}

// A name from input with an ESC sequence and a newline neither drives the terminal nor breaks the
// table's lines, and the columns stay aligned on the escaped text.
TEST(Table, ControlCharactersInCellsEscaped) {
  report::Table t({"scenario", "n"});
  t.add_row({"a\x1b[2J\nb", "1"});
  t.add_row({"plain", "22"});
  EXPECT_EQ(t.render(),
            "scenario     n\n"
            "---------------\n"
            "a\\x1b[2J\\nb   1\n"
            "plain        22\n");
}
