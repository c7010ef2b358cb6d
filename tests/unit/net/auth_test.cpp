// Tokens from a file or the environment, the constant-time comparison's results, the loopback rule.
#include "m2mlat/net/auth.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "m2mlat/core/error.hpp"

namespace m2mlat::net {
namespace {

struct TokenFile {
  std::string path =
      (std::filesystem::temp_directory_path() / ("m2mlat-token-" + std::to_string(::getpid()))).string();
  explicit TokenFile(const std::string& text, ::mode_t mode = 0600) {
    std::ofstream(path) << text;
    ::chmod(path.c_str(), mode);
  }
  ~TokenFile() { std::filesystem::remove(path); }
};

TEST(Auth, TokenFromFileTrimmedAndPreferredToTheEnvironment) {
  ::setenv("M2MLAT_TOKEN", "environment-token-0123456789", 1);
  {
    TokenFile file("  file-token-0123456789abcdef \nsecond line\n");
    EXPECT_EQ(load_token(file.path), "file-token-0123456789abcdef");
  }
  EXPECT_EQ(load_token(std::nullopt), "environment-token-0123456789");
  ::setenv("M2MLAT_TOKEN", "", 1);
  EXPECT_FALSE(load_token(std::nullopt).has_value());
  ::unsetenv("M2MLAT_TOKEN");
  EXPECT_FALSE(load_token(std::nullopt).has_value());
}

TEST(Auth, ShortOrUnsendableTokensAndMissingFilesAreRefused) {
  {
    TokenFile file("short\n");
    EXPECT_THROW(load_token(file.path), core::Error);
  }
  {
    TokenFile file("has a space in it 0123456789\n");
    EXPECT_THROW(load_token(file.path), core::Error);
  }
  try {
    load_token(std::string("/nonexistent/token"));
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::no_input);
  }
}

// A token file others could read (or write) is refused with the way to fix it; the owner's alone
// (0600, 0400) is taken, and 0640 only on a file owned by root.
TEST(Auth, ATokenFileOthersCanAccessIsRefused) {
  const auto refused = [](const TokenFile& file) {
    try {
      load_token(file.path);
      return ::testing::AssertionFailure() << "accepted";
    } catch (const core::Error& e) {
      if (e.kind() != core::ErrorKind::usage) return ::testing::AssertionFailure() << e.what();
      if (std::string(e.what()).find("chmod 600 " + file.path) == std::string::npos)
        return ::testing::AssertionFailure() << "no fix in: " << e.what();
      return ::testing::AssertionSuccess();
    }
  };
  for (const ::mode_t mode : {0644, 0604, 0602, 0660, 0620, 0610, 0666})
    EXPECT_TRUE(refused(TokenFile("file-token-0123456789abcdef\n", mode))) << std::oct << mode;
  for (const ::mode_t mode : {0600, 0400}) {
    TokenFile file("file-token-0123456789abcdef\n", mode);
    EXPECT_EQ(load_token(file.path), "file-token-0123456789abcdef");
  }
  // Group read: only on a file of root's (root reads any file, so the test can give it away).
  TokenFile file("file-token-0123456789abcdef\n", 0640);
  if (::geteuid() == 0) {
    EXPECT_EQ(load_token(file.path), "file-token-0123456789abcdef");
    ASSERT_EQ(::chown(file.path.c_str(), 65534, 65534), 0);
  }
  EXPECT_TRUE(refused(file));
}

TEST(Auth, TokensEqualOnlyWhenIdentical) {
  EXPECT_TRUE(tokens_equal("abcdefghijklmnop", "abcdefghijklmnop"));
  EXPECT_TRUE(tokens_equal("", ""));
  EXPECT_FALSE(tokens_equal("abcdefghijklmnop", "abcdefghijklmnoq"));
  EXPECT_FALSE(tokens_equal("abcdefghijklmnop", "abcdefghijklmno"));
  EXPECT_FALSE(tokens_equal("abcdefghijklmno", "abcdefghijklmnop"));
  EXPECT_FALSE(tokens_equal("abc", std::string_view("abc\0", 4)));
  EXPECT_FALSE(tokens_equal("", "a"));
}

TEST(Auth, Loopback) {
  for (const char* yes : {"127.0.0.1", "127.1.2.3", "::1", "[::1]", "localhost", "::ffff:127.0.0.1"})
    EXPECT_TRUE(is_loopback(yes)) << yes;
  for (const char* no : {"0.0.0.0", "::", "10.0.0.2", "128.0.0.1", "192.168.1.1", "fe80::1", "example.com",
                         "", "127.0.0.1.evil", "::ffff:10.0.0.1"})
    EXPECT_FALSE(is_loopback(no)) << no;
}

}  // namespace
}  // namespace m2mlat::net
