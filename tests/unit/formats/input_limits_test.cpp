// The limits every reader shares: a last line cut mid-write is refused in every format (naming
// file:line), a line longer than 64 KiB is refused (from a file and, as it streams, from a pipe), a
// device is no input file, and a JSON Lines record with a member given twice is refused.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "formats_test_support.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/formats/input_text.hpp"

namespace m2mlat::formats {
namespace {

using test::expect_data_error;
using test::fixture;

std::string read_whole(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

ImportOptions with_node() {
  ImportOptions options;
  options.node = "operator";
  return options;
}

// Every format's fixture with its last line cut in the middle (the newline and the last few
// characters gone) is refused, naming the file and that line; the intact file is accepted.
TEST(InputLimits, ALastLineCutMidWriteIsRefusedInEveryFormat) {
  for (const char* name : {"dmesg_mixed.log", "kmsg_records.log", "events_small.csv", "events_small.jsonl",
                           "rig_export_two_pins.csv", "rig_paired_small.csv", "rig_sync_small.csv"}) {
    SCOPED_TRACE(name);
    const std::string whole = read_whole(fixture(name));
    ASSERT_FALSE(whole.empty());
    ASSERT_EQ(whole.back(), '\n');
    EXPECT_NO_THROW(import_text(whole, name, std::nullopt, with_node()));
    const std::string cut = whole.substr(0, whole.find_last_not_of("\r\n") + 1 - 4);  // blank tail too
    const auto line = std::count(cut.begin(), cut.end(), '\n') + 1;
    const std::string where = std::string(name) + ":" + std::to_string(line) + ":";
    expect_data_error([&] { import_text(cut, name, std::nullopt, with_node()); }, {where, "newline"});
  }
}

TEST(InputLimits, TheTruncatedKernelLogLineOfTheIssueIsNotAnEvent) {
  const std::string text = "GPIO_16_IRQ:1700000000000000000\nGPIO_16_IRQ:17000";
  expect_data_error([&] { import_text(text, "k.log", Format::kernel_log, with_node()); },
                    {"k.log:2:", "cut mid-write", "GPIO_16_IRQ:17000"});
  // The timestamp scan of `stats` and `pair` refuses it too.
  const auto path =
      (std::filesystem::temp_directory_path() / ("m2mlat-cut-" + std::to_string(::getpid()) + ".log"))
          .string();
  std::ofstream(path) << text;
  expect_data_error([&] { read_timestamps(path, Format::kernel_log); }, {path + ":2:"});
  std::filesystem::remove(path);
}

TEST(InputLimits, ASingleLineWithoutNewlineAndABlankTailAreAccepted) {
  const auto one = import_text("GPIO_16_IRQ:1700000000000000000", "one.log", Format::kernel_log, with_node());
  EXPECT_EQ(std::get<EventImport>(one.content).events.size(), 1u);
  const auto blank =
      import_text("GPIO_16_IRQ:1700000000000000000\n  \t", "blank.log", Format::kernel_log, with_node());
  EXPECT_EQ(std::get<EventImport>(blank.content).events.size(), 1u);
  const auto crlf = import_text("node,channel,time_ns\r\na,b,1\r\n", "crlf.csv", std::nullopt, {});
  EXPECT_EQ(std::get<EventImport>(crlf.content).events.size(), 1u);
  // A CRLF file cut between its CR and LF has lost its line end too.
  expect_data_error([] { import_text("node,channel,time_ns\r\na,b,1\r", "cr.csv", std::nullopt, {}); },
                    {"cr.csv:2:"});
}

TEST(InputLimits, LinesUpTo64KiBAreReadAndALongerOneIsRefusedWithItsLine) {
  const std::string exact(kMaxLineBytes, 'x');
  EXPECT_NO_THROW(check_line_lengths("a\n" + exact + "\nb\n", "ok.log"));
  EXPECT_NO_THROW(check_line_lengths("a\n" + exact, "ok.log"));
  expect_data_error([&] { check_line_lengths("a\nb\n" + exact + "y\nc\n", "long.log"); },
                    {"long.log:3:", "longer than 65536 bytes"});
  // Through an importer, with the line in the middle of valid records.
  const std::string text = "node,channel,time_ns\na,b,1\na,b," + std::string(100'000, '7') + "\na,b,3\n";
  expect_data_error([&] { import_text(text, "long.csv", std::nullopt, {}); }, {"long.csv:3:"});
}

TEST(InputLimits, ADeviceIsNoInputFile) {
  const auto start = std::chrono::steady_clock::now();
  try {
    InputText::read_file("/dev/zero");
    ADD_FAILURE() << "/dev/zero was read";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::no_input);
    EXPECT_NE(std::string(e.what()).find("/dev/zero: is not a regular file or a pipe"), std::string::npos)
        << e.what();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
}

// A pipe that never ends and holds no newline: refused once the line passes the limit, with the
// memory of one line or so, not grown until the machine runs out.
TEST(InputLimits, AnEndlessPipeWithoutNewlinesIsRefusedAtTheLineLimit) {
  const auto path =
      (std::filesystem::temp_directory_path() / ("m2mlat-fifo-" + std::to_string(::getpid()))).string();
  std::filesystem::remove(path);
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  std::signal(SIGPIPE, SIG_IGN);  // the writer learns of the reader's end by EPIPE
  std::thread writer([&] {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) return;
    const std::string zeros(1 << 16, '\0');
    std::size_t written = 0;
    while (written < (std::size_t{1} << 30)) {  // stops at EPIPE long before 1 GiB
      const auto n = ::write(fd, zeros.data(), zeros.size());
      if (n <= 0) break;
      written += static_cast<std::size_t>(n);
    }
    ::close(fd);
  });
  expect_data_error([&] { InputText::read_file(path); }, {path + ":1:", "longer than 65536 bytes"});
  writer.join();
  std::filesystem::remove(path);
}

TEST(InputLimits, AJsonLinesMemberGivenTwiceIsRefused) {
  const std::string text =
      "{\"format\":\"m2mlat-events/1\",\"node\":\"a\",\"channel\":\"w\",\"time_ns\":1}\n"
      "{\"format\":\"m2mlat-events/1\",\"node\":\"a\",\"channel\":\"w\",\"time_ns\":2,\"time_ns\":3}\n";
  expect_data_error([&] { import_text(text, "dup.jsonl", std::nullopt, {}); },
                    {"dup.jsonl:2:", "member 'time_ns' appears twice"});
  expect_data_error(
      [] {
        import_text(
            "{\"format\":\"m2mlat-events/1\",\"format\":\"m2mlat-events/1\",\"node\":\"a\","
            "\"channel\":\"w\",\"time_ns\":1}\n",
            "f.jsonl", Format::events_jsonl, {});
      },
      {"f.jsonl:1:", "member 'format' appears twice"});
  // The same key in two different objects is no repetition (the inner one is refused for its type).
  expect_data_error(
      [] {
        import_text(
            "{\"format\":\"m2mlat-events/1\",\"node\":{\"node\":1},\"channel\":\"w\",\"time_ns\":1}\n",
            "n.jsonl", Format::events_jsonl, {});
      },
      {"n.jsonl:1:", "field node", "is not a string"});
}

TEST(InputLimits, ACsvHeaderColumnGivenTwiceIsRefused) {
  expect_data_error([] { import_text("node,channel,node,time_ns\na,b,c,1\n", "h.csv", std::nullopt, {}); },
                    {"h.csv:1:", "header column 'node' appears twice"});
}

}  // namespace
}  // namespace m2mlat::formats
