// Line diff by longest common subsequence (diff.hpp).
#include "m2mlat/setup/diff.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

namespace m2mlat::setup {

namespace {

std::vector<std::string_view> split_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  std::size_t pos = 0;
  while (pos < text.size()) {
    auto end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    lines.push_back(text.substr(pos, end - pos));
    pos = end + 1;
  }
  return lines;
}

}  // namespace

std::string line_diff(std::string_view before, std::string_view after, std::string_view name) {
  if (before == after) return {};
  const auto a = split_lines(before);
  const auto b = split_lines(after);
  const std::size_t n = a.size(), m = b.size();
  // lcs[i][j]: length of the longest common subsequence of a[i..] and b[j..].
  std::vector<std::vector<std::size_t>> lcs(n + 1, std::vector<std::size_t>(m + 1, 0));
  for (std::size_t i = n; i-- > 0;)
    for (std::size_t j = m; j-- > 0;)
      lcs[i][j] = a[i] == b[j] ? lcs[i + 1][j + 1] + 1 : std::max(lcs[i + 1][j], lcs[i][j + 1]);
  std::string out = fmt::format("--- {} (now)\n+++ {} (new)\n", name, name);
  std::size_t i = 0, j = 0;
  while (i < n || j < m) {
    if (i < n && j < m && a[i] == b[j]) {
      out += fmt::format(" {}\n", a[i]);
      ++i, ++j;
    } else if (i < n && (j == m || lcs[i + 1][j] >= lcs[i][j + 1])) {
      out += fmt::format("-{}\n", a[i++]);  // removals first, as diff -u shows them
    } else {
      out += fmt::format("+{}\n", b[j++]);
    }
  }
  if (!before.empty() && before.back() != '\n') out += "\\ the current file has no newline at its end\n";
  return out;
}

}  // namespace m2mlat::setup
