// /proc/interrupts parsing and /proc/irq/N/smp_affinity_list.
#include "m2mlat/rt/irq.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "m2mlat/core/number.hpp"

namespace m2mlat::rt {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::string_view next_word(std::string_view& s) {
  s = trim(s);
  const auto end = s.find_first_of(" \t");
  const auto word = s.substr(0, end);
  s = end == std::string_view::npos ? std::string_view{} : s.substr(end);
  return word;
}

std::optional<std::string> read_text(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The handlers' names: the description's last word, and before it every word ending in ','
// ("... Edge  eth0-rx, eth0-tx").
std::vector<std::string> split_actions(std::string_view description) {
  std::vector<std::string> words;
  for (auto rest = description; !trim(rest).empty();) words.emplace_back(next_word(rest));
  std::vector<std::string> actions;
  if (words.empty()) return actions;
  std::size_t first = words.size() - 1;
  while (first > 0 && words[first - 1].size() > 1 && words[first - 1].back() == ',') --first;
  for (std::size_t i = first; i < words.size(); ++i) {
    auto w = words[i];
    if (!w.empty() && w.back() == ',') w.pop_back();
    actions.push_back(w);
  }
  return actions;
}

}  // namespace

std::vector<InterruptLine> parse_interrupts(std::string_view text) {
  std::vector<InterruptLine> lines;
  std::size_t cpus = 0;
  bool header = true;
  while (!text.empty()) {
    const auto nl = text.find('\n');
    auto row = text.substr(0, nl);
    text = nl == std::string_view::npos ? std::string_view{} : text.substr(nl + 1);
    if (header) {  // "           CPU0       CPU1": the number of count columns
      for (auto rest = row; !trim(rest).empty();)
        if (next_word(rest).starts_with("CPU")) ++cpus;
      header = false;
      continue;
    }
    auto rest = row;
    const auto label = next_word(rest);
    if (label.size() < 2 || label.back() != ':') continue;
    InterruptLine line;
    if (!core::parse_integer(label.substr(0, label.size() - 1), line.irq)) continue;  // NMI:, LOC:, ...
    for (std::size_t c = 0; c < cpus; ++c) {
      auto probe = rest;
      const auto word = next_word(probe);
      std::uint64_t count = 0;
      if (!core::parse_integer(word, count)) break;
      line.counts.push_back(count);
      rest = probe;
    }
    line.description = std::string(trim(rest));
    line.actions = split_actions(line.description);
    lines.push_back(std::move(line));
  }
  return lines;
}

std::vector<int> find_irq_in_interrupts(std::string_view interrupts_text, std::string_view consumer) {
  std::vector<int> irqs;
  for (const auto& line : parse_interrupts(interrupts_text))
    for (const auto& action : line.actions)
      if (action == consumer) {
        irqs.push_back(line.irq);
        break;
      }
  return irqs;
}

std::vector<int> find_irq_by_consumer(std::string_view consumer, const std::string& proc_root) {
  const auto text = read_text(proc_root + "/interrupts");
  return text ? find_irq_in_interrupts(*text, consumer) : std::vector<int>{};
}

Outcome pin_irq(int irq, int cpu, const std::string& proc_root) {
  const auto path = fmt::format("{}/irq/{}/smp_affinity_list", proc_root, irq);
  // A kernel file, written in place on purpose: it is not a regular file, and the value only takes
  // effect when written into this very inode (core::write_output_file would refuse it, and a rename
  // over it is not possible in /proc).
  std::FILE* file = std::fopen(path.c_str(), "w");
  int err = 0;
  if (file == nullptr) {
    err = errno;
  } else {
    // The kernel checks the value when the buffer is written: a refusal shows at fflush/fclose.
    const bool written = std::fprintf(file, "%d\n", cpu) > 0 && std::fflush(file) == 0;
    if (!written) err = errno;
    if (std::fclose(file) != 0 && err == 0) err = errno;
  }
  if (err == 0) return Outcome::success(fmt::format("IRQ {} routed to CPU {}", irq, cpu));
  if (err == EACCES || err == EPERM)
    return Outcome::failure(fmt::format(
        "routing IRQ {} to CPU {} not permitted: {} is writable by root only (run the recorder as root for "
        "--irq-cpu, or write the CPU there once as root)",
        irq, cpu, path));
  if (err == ENOENT) return Outcome::failure(fmt::format("IRQ {} has no {}", irq, path));
  if (err == EINVAL || err == EIO)
    return Outcome::failure(fmt::format(
        "the interrupt controller refused to route IRQ {} to CPU {} ({}): some GPIO controllers deliver all "
        "their interrupts through one parent IRQ; pin that one instead",
        irq, cpu, std::strerror(err)));
  return Outcome::failure(fmt::format("routing IRQ {} to CPU {}: {}", irq, cpu, std::strerror(err)));
}

std::optional<std::string> irq_affinity(int irq, const std::string& proc_root) {
  for (const char* name : {"effective_affinity_list", "smp_affinity_list"}) {
    if (auto text = read_text(fmt::format("{}/irq/{}/{}", proc_root, irq, name))) {
      const auto value = trim(*text);
      if (!value.empty()) return std::string(value);
    }
  }
  return std::nullopt;
}

}  // namespace m2mlat::rt
