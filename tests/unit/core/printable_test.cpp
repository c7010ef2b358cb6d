// Escaping text from input for the terminal.
#include "m2mlat/core/printable.hpp"

#include <gtest/gtest.h>

using m2mlat::core::printable;

TEST(Printable, PlainTextAndUtf8Unchanged) {
  EXPECT_EQ(printable("station-1 node_2.x"), "station-1 node_2.x");
  EXPECT_EQ(printable("874.5 µs ± 3 — Zürich 東京"), "874.5 µs ± 3 — Zürich 東京");
  EXPECT_EQ(printable(""), "");
  EXPECT_EQ(printable("a\\x1b"), "a\\x1b");  // a backslash stays as it is
}

TEST(Printable, C0ControlsAndDelEscaped) {
  EXPECT_EQ(printable("ve\x1b[2Jhicle"), "ve\\x1b[2Jhicle");
  EXPECT_EQ(printable("a\nb\rc\td"), "a\\nb\\rc\\td");
  EXPECT_EQ(printable(std::string_view("\0\x07\x7f", 3)), "\\x00\\x07\\x7f");
  EXPECT_EQ(printable("\x1b]0;owned\x07"), "\\x1b]0;owned\\x07");  // a window-title change
}

TEST(Printable, C1ControlsAndBidiOverridesEscaped) {
  EXPECT_EQ(printable("x\xc2\x9b"
                      "31mred"),
            "x\\u009b31mred");                  // U+009B: an 8-bit CSI
  EXPECT_EQ(printable("\xc2\x85"), "\\u0085");  // NEL
  EXPECT_EQ(printable("abc\xe2\x80\xae"
                      "fed"),
            "abc\\u202efed");  // right-to-left override
  EXPECT_EQ(printable("\xe2\x81\xa6"
                      "x"),
            "\\u2066x");  // left-to-right isolate
}

TEST(Printable, InvalidUtf8BytesEscaped) {
  EXPECT_EQ(printable("\x9b"
                      "31m"),
            "\\x9b31m");  // a raw C1 byte: CSI on 8-bit terminals
  EXPECT_EQ(printable("a\xff"
                      "b"),
            "a\\xffb");
  EXPECT_EQ(printable("\xc3"), "\\xc3");                    // a cut sequence
  EXPECT_EQ(printable("\xc0\xaf"), "\\xc0\\xaf");           // an overlong '/'
  EXPECT_EQ(printable("\xed\xa0\x80"), "\\xed\\xa0\\x80");  // a surrogate
}
