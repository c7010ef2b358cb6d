// The output-file writer against a real file system: what it refuses, what it leaves behind, and
// the modes it gives.
#include "m2mlat/core/output_file.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "m2mlat/core/error.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using m2mlat::core::Error;
using m2mlat::core::ErrorKind;
using m2mlat::core::OutputFileOptions;
using m2mlat::core::write_output_file;

namespace {

// A real write(2) failure for the tests: a file size limit, so that writing past `bytes` fails
// with EFBIG (the signal that would come with it is ignored meanwhile).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    EXPECT_EQ(::getrlimit(RLIMIT_FSIZE, &old_), 0);
    old_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    struct rlimit limit = old_;
    limit.rlim_cur = bytes;
    EXPECT_EQ(::setrlimit(RLIMIT_FSIZE, &limit), 0);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &old_);
    std::signal(SIGXFSZ, old_handler_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  struct rlimit old_ {};
  void (*old_handler_)(int) = nullptr;
};

class OutputFile : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  static std::string read(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  static void write_plain(const std::string& p, const std::string& text) { std::ofstream(p) << text; }
  std::set<std::string> names() const {
    std::set<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.insert(e.path().filename().string());
    return out;
  }
  static mode_t mode_of(const std::string& p) {
    struct stat st {};
    EXPECT_EQ(::lstat(p.c_str(), &st), 0) << p;
    return st.st_mode;
  }
  // The message of the core::Error(io) that writing `target` throws.
  static std::string refusal(const std::string& target) {
    try {
      write_output_file(target, std::string_view("new\n"));
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::io) << e.what();
      return e.what();
    }
    ADD_FAILURE() << target << " was written";
    return {};
  }

  m2mlat::testing::TempDir temp_;
  const fs::path dir_ = temp_.path();
};

TEST_F(OutputFile, NewFileGetsContentAndUmaskMode) {
  const mode_t old = ::umask(027);
  write_output_file(path("out.csv"), std::string_view("a,b\n1,2\n"));
  ::umask(old);
  EXPECT_EQ(read(path("out.csv")), "a,b\n1,2\n");
  EXPECT_EQ(mode_of(path("out.csv")) & 07777, 0640u);  // 0666 & ~027
  EXPECT_EQ(names(), std::set<std::string>{"out.csv"});
}

TEST_F(OutputFile, ExistingRegularFileReplacedKeepingItsMode) {
  write_plain(path("out.csv"), "old content that is longer\n");
  ASSERT_EQ(::chmod(path("out.csv").c_str(), 0600), 0);
  write_output_file(path("out.csv"), std::string_view("new\n"));
  EXPECT_EQ(read(path("out.csv")), "new\n");
  EXPECT_EQ(mode_of(path("out.csv")) & 07777, 0600u);
  EXPECT_EQ(names(), std::set<std::string>{"out.csv"});
}

TEST_F(OutputFile, ExplicitModeWins) {
  write_plain(path("chrony.conf"), "old\n");
  ASSERT_EQ(::chmod(path("chrony.conf").c_str(), 0600), 0);
  write_output_file(path("chrony.conf"), std::string_view("new\n"), OutputFileOptions{.mode = 0644});
  EXPECT_EQ(mode_of(path("chrony.conf")) & 07777, 0644u);
}

TEST_F(OutputFile, SymlinkTargetRefusedAndLinkedFileUnchanged) {
  write_plain(path("victim"), "precious\n");
  fs::create_symlink(path("victim"), path("out.csv"));
  const auto message = refusal(path("out.csv"));
  EXPECT_NE(message.find(path("out.csv")), std::string::npos) << message;
  EXPECT_NE(message.find("a symbolic link"), std::string::npos) << message;
  EXPECT_TRUE(S_ISLNK(mode_of(path("out.csv"))));
  EXPECT_EQ(read(path("victim")), "precious\n");
  EXPECT_EQ(names(), (std::set<std::string>{"out.csv", "victim"}));
}

TEST_F(OutputFile, DanglingSymlinkTargetRefused) {
  fs::create_symlink(path("nowhere"), path("out.csv"));
  EXPECT_NE(refusal(path("out.csv")).find("a symbolic link"), std::string::npos);
  EXPECT_FALSE(fs::exists(path("nowhere")));
}

// The old writer used "<target>.tmp": a link planted under that name redirected the write. The
// temporary now has a random name, is created with O_EXCL|O_NOFOLLOW, and is a regular file.
TEST_F(OutputFile, PlantedTemporaryNamesAreNotFollowed) {
  write_plain(path("victim"), "precious\n");
  fs::create_symlink(path("victim"), path("out.csv.tmp"));
  fs::create_symlink(path("victim"), path(".out.csv.tmp"));
  std::set<std::string> temporaries;
  for (int i = 0; i < 2; ++i)
    write_output_file(path("out.csv"), [&](std::ostream& out) {
      out << "new\n";
      for (const auto& name : names()) {
        if (name == "victim" || name == "out.csv" || name == "out.csv.tmp" || name == ".out.csv.tmp")
          continue;
        temporaries.insert(name);
        EXPECT_TRUE(S_ISREG(mode_of(path(name)))) << name;
        EXPECT_EQ(name.rfind(".out.csv.", 0), 0u) << name;  // hidden, beside the target
      }
    });
  EXPECT_EQ(temporaries.size(), 2u);  // one per write, each under a new random name
  EXPECT_EQ(read(path("victim")), "precious\n");
  EXPECT_EQ(read(path("out.csv")), "new\n");
  EXPECT_EQ(names(), (std::set<std::string>{"out.csv", "out.csv.tmp", ".out.csv.tmp", "victim"}));
}

TEST_F(OutputFile, CharacterDeviceRefusedAndLeftADevice) {
  const auto message = refusal("/dev/null");
  EXPECT_NE(message.find("/dev/null"), std::string::npos) << message;
  EXPECT_NE(message.find("a character device"), std::string::npos) << message;
  EXPECT_TRUE(S_ISCHR(mode_of("/dev/null")));
}

TEST_F(OutputFile, FileThisProcessHasOpenRefusedUntilClosed) {
  write_plain(path("store.db"), "held\n");
  {
    std::ifstream held(path("store.db"));  // an input still being read (or a store's connection)
    ASSERT_TRUE(held.is_open());
    EXPECT_NE(refusal(path("store.db")).find("an input of this command"), std::string::npos);
    EXPECT_EQ(read(path("store.db")), "held\n");
  }
  write_output_file(path("store.db"), std::string_view("new\n"));
  EXPECT_EQ(read(path("store.db")), "new\n");
}

TEST_F(OutputFile, DirectoryRefused) {
  fs::create_directory(path("sub"));
  EXPECT_NE(refusal(path("sub")).find("a directory"), std::string::npos);
  EXPECT_TRUE(fs::is_empty(path("sub")));
  EXPECT_NE(refusal(dir_.string() + "/").find("a directory"), std::string::npos);
}

TEST_F(OutputFile, FifoRefusedWithoutBlocking) {
  ASSERT_EQ(::mkfifo(path("pipe").c_str(), 0600), 0);
  EXPECT_NE(refusal(path("pipe")).find("a FIFO"), std::string::npos);
  EXPECT_TRUE(S_ISFIFO(mode_of(path("pipe"))));
}

TEST_F(OutputFile, MissingFolderNamed) {
  const auto message = refusal(path("no/such/out.csv"));
  EXPECT_NE(message.find(path("no/such/out.csv")), std::string::npos) << message;
  EXPECT_NE(message.find("No such file or directory"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(path("no")));
}

TEST_F(OutputFile, FailingWriterLeavesTargetAndNoTemporary) {
  write_plain(path("out.csv"), "old\n");
  EXPECT_THROW(write_output_file(path("out.csv"),
                                 [](std::ostream& out) {
                                   out << std::string(200000, 'x');  // past the buffer: on disk
                                   throw Error(ErrorKind::data, "input.csv:3: bad field");
                                 }),
               Error);
  EXPECT_EQ(read(path("out.csv")), "old\n");
  EXPECT_EQ(names(), std::set<std::string>{"out.csv"});
}

// A real write(2) failure: a file size limit (EFBIG) in the middle of the content.
TEST_F(OutputFile, WriteErrorReportedAndNothingLeftBehind) {
  write_plain(path("out.csv"), "old\n");
  std::string message;
  try {
    const FileSizeLimit limit(100000);  // only while writing: gtest's own output may be a file
    write_output_file(path("out.csv"), std::string(1 << 20, 'x'));
  } catch (const Error& e) {
    message = e.what();
    EXPECT_EQ(e.kind(), ErrorKind::io);
  }
  EXPECT_NE(message.find(path("out.csv")), std::string::npos) << message;
  EXPECT_NE(message.find("File too large"), std::string::npos) << message;
  EXPECT_EQ(read(path("out.csv")), "old\n");
  EXPECT_EQ(names(), std::set<std::string>{"out.csv"});
}

// A writer that stops on the failed stream with its own error: the message says why, with the path.
TEST_F(OutputFile, WriterStoppedByAWriteErrorReportsTheReason) {
  std::string message;
  try {
    const FileSizeLimit limit(100000);
    write_output_file(path("out.csv"), [](std::ostream& out) {
      for (int i = 0; i < 100 && out; ++i) out << std::string(1 << 16, 'x');
      if (!out) throw Error(ErrorKind::io, "writing the export failed");
    });
  } catch (const Error& e) {
    message = e.what();
  }
  EXPECT_NE(message.find(path("out.csv") + ": write failed: File too large"), std::string::npos) << message;
  EXPECT_TRUE(names().empty());
}

TEST_F(OutputFile, DashIsStandardOutput) {
  ::testing::internal::CaptureStdout();
  write_output_file("-", std::string_view("to stdout\n"));
  EXPECT_EQ(::testing::internal::GetCapturedStdout(), "to stdout\n");
  EXPECT_FALSE(fs::exists("-"));
}

TEST_F(OutputFile, CheckTarget) {
  EXPECT_FALSE(m2mlat::core::check_output_target(path("new.csv")));
  write_plain(path("old.csv"), "x");
  EXPECT_TRUE(m2mlat::core::check_output_target(path("old.csv")));
  EXPECT_THROW((void)m2mlat::core::check_output_target("/dev/null"), Error);
}

}  // namespace
