// Tokens from a file or the environment, the constant-time comparison's results, the loopback rule.
#include "m2mlat/net/auth.hpp"

#include <gtest/gtest.h>
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
  explicit TokenFile(const std::string& text) { std::ofstream(path) << text; }
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
