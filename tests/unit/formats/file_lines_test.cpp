// A file read block by block gives what reading it whole gives: the same lines and line numbers
// across block boundaries, and for kernel logs the same timestamp series or the same error (the
// whole-file checks, a line too long or a last line cut mid-write, before a bad line's own).
#include "m2mlat/formats/file_lines.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/kernel_log.hpp"

namespace m2mlat::formats {
namespace {

class FileLinesTest : public ::testing::Test {
 protected:
  void TearDown() override { std::filesystem::remove(path_); }
  const std::string& write(const std::string& text) {
    std::ofstream(path_, std::ios::binary) << text;
    return path_;
  }
  std::string path_ = (std::filesystem::temp_directory_path() /
                       ("m2mlat-file-lines-" + std::to_string(::getpid()) + ".log"))
                          .string();
};

// Lines of 0 to 64 KiB (CRLF and LF) through the smallest buffer: every line and number as LineReader's.
TEST_F(FileLinesTest, TheSameLinesAndNumbersAcrossBlocks) {
  std::mt19937 rng(19);
  std::string text = "\xEF\xBB\xBF";
  for (int i = 0; i < 400; ++i) {
    const std::size_t length = i % 50 == 7 ? kMaxLineBytes : rng() % (i % 3 == 0 ? 4000 : 60);
    text += std::string(length, static_cast<char>('a' + i % 26));
    text += i % 5 == 0 ? "\r\n" : "\n";
  }
  text += "\xEF\xBB\xBF not a mark here\n";
  FileLines blocks(write(text), 0);  // the smallest buffer: twice the longest line
  LineReader whole(text);
  std::string_view a, b;
  while (whole.next(a)) {
    ASSERT_TRUE(blocks.next(b)) << whole.line_number();
    ASSERT_EQ(a, b) << whole.line_number();
    ASSERT_EQ(whole.line_number(), blocks.line_number());
  }
  EXPECT_FALSE(blocks.next(b));
}

// What reading the whole text gives: the series, or the error's message.
std::string outcome(const std::function<std::vector<TimestampSeries>()>& read) {
  try {
    std::string out;
    for (const auto& s : read()) {
      out += s.label + ":" + std::to_string(s.ns.size()) + ":" + std::to_string(s.log_time_us.size());
      for (std::size_t i = 0; i < s.ns.size(); ++i) out += "," + std::to_string(s.ns[i]);
      for (const auto us : s.log_time_us) out += ";" + std::to_string(us);
    }
    return out;
  } catch (const core::Error& e) {
    return std::string("error: ") + e.what();
  }
}

TEST_F(FileLinesTest, KernelLogTimestampsAndErrorsAsWhenReadWhole) {
  std::string lines;
  for (int i = 0; i < 60000; ++i)  // ~2.9 MB: three blocks
    lines += "[ " + std::to_string(1000 + i) + ".654071] GPIO_" + (i % 7 == 0 ? "17" : "16") + "_IRQ:" +
             std::to_string(1780304404654101829 + 1000 * i) + "\n";
  const auto at_line = [&](int n) { return lines.find("\n" + std::string("[ ") + std::to_string(1000 + n - 1) + ".") + 1; };
  const std::string bad = "GPIO_16_IRQ:12ab\n";
  std::vector<std::string> texts{
      lines,
      "\xEF\xBB\xBF" + lines,
      lines.substr(0, at_line(30000)) + bad + lines.substr(at_line(30000)),  // a bad line
      lines + bad + lines.substr(0, 40),                                     // ... and a cut last line after it
      lines.substr(0, 100) + bad + lines.substr(100, at_line(50000) - 100) + std::string(kMaxLineBytes + 1, 'x') +
          "\n" + lines.substr(at_line(50000)),  // a bad line, then one too long
      "", "\xEF\xBB\xBF", "GPIO_16_IRQ:1700000000000000000", lines + "  ", "\n\n", "no record here\n",
      "GPIO_16_IRQ:1\r\nGPIO_16_IRQ:2\r\n"};
  for (const auto& text : texts) {
    SCOPED_TRACE(text.substr(0, 60));
    const auto& path = write(text);
    const auto whole = outcome([&] {
      const auto input = InputText::from_string(text, path);
      check_input(input.text(), input.name());
      return scan_kernel_log_timestamps(input.text(), input.name(), "");
    });
    EXPECT_EQ(outcome([&] { return read_kernel_log_timestamps(path); }), whole);
    if (text == lines) {  // one pin of two
      EXPECT_EQ(outcome([&] { return read_kernel_log_timestamps(path, "17"); }).substr(0, 8), "17:8572:");
    }
  }
}

}  // namespace
}  // namespace m2mlat::formats
