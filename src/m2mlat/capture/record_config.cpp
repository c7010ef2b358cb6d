// TOML -> RecordConfig with toml++, which keeps every node's source position for the messages.
#include "m2mlat/capture/record_config.hpp"

#include <fmt/format.h>

// Header-only: Debian ships toml++ as a shared library only, and the real-kernel tests link m2mlat
// statically.
#define TOML_HEADER_ONLY 1
#include <toml++/toml.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/input_text.hpp"

namespace m2mlat::capture {

namespace {

class Reader {
 public:
  explicit Reader(std::string name) : name_(std::move(name)) {}

  [[noreturn]] void fail(const toml::source_region& where, const std::string& key,
                         const std::string& what) const {
    throw core::Error(core::ErrorKind::data, fmt::format("{}:{}:{}: {}: {}", name_, where.begin.line,
                                                         where.begin.column, key, what));
  }

  std::string string(const toml::node& node, const std::string& key) const {
    if (const auto* s = node.as_string()) return s->get();
    fail(node.source(), key, "expected a string");
  }

  bool boolean(const toml::node& node, const std::string& key) const {
    if (const auto* b = node.as_boolean()) return b->get();
    fail(node.source(), key, "expected true or false");
  }

  std::int64_t integer(const toml::node& node, const std::string& key, std::int64_t low,
                       std::int64_t high) const {
    const auto* i = node.as_integer();
    if (i == nullptr) fail(node.source(), key, "expected an integer");
    if (i->get() < low || i->get() > high)
      fail(node.source(), key, fmt::format("must be in {}..{}", low, high));
    return i->get();
  }

  // "10ms", "1.5s", "250us"; the integer 0 means none.
  core::Duration duration(const toml::node& node, const std::string& key) const {
    if (const auto* i = node.as_integer(); i != nullptr && i->get() == 0) return core::Duration{0};
    const auto text = string(node, key);
    try {
      const auto d = text == "0" ? core::Duration{0} : core::parse_duration(text);
      if (d.count() < 0) fail(node.source(), key, "must not be negative");
      return d;
    } catch (const core::Error& e) {
      if (e.kind() == core::ErrorKind::data) throw;
      fail(node.source(), key, fmt::format("'{}' is not a duration with a unit (e.g. \"10ms\")", text));
    }
  }

  // A word parsed by one of channel.hpp's parsers (which throw usage errors listing the choices).
  template <typename Parse>
  auto word(const toml::node& node, const std::string& key, Parse parse) const {
    const auto text = string(node, key);
    try {
      return parse(text);
    } catch (const core::Error& e) {
      if (e.kind() == core::ErrorKind::data) throw;
      fail(node.source(), key, e.what());
    }
  }

  ChannelSpec channel(const toml::table& table, const std::string& prefix,
                      std::set<std::string>& keys) const {
    ChannelSpec spec;
    for (auto&& [k, v] : table) {
      const std::string key(k.str());
      const auto full = prefix + "." + key;
      keys.insert(key);
      if (key == "name")
        spec.name = string(v, full);
      else if (key == "chip")
        spec.chip = string(v, full);
      else if (key == "line")
        spec.line = v.is_integer() ? std::to_string(integer(v, full, 0, 65535)) : string(v, full);
      else if (key == "edges")
        spec.edges = word(v, full, parse_edges);
      else if (key == "bias")
        spec.bias = word(v, full, parse_bias);
      else if (key == "active_low")
        spec.active_low = boolean(v, full);
      else if (key == "clock")
        spec.clock = word(v, full, parse_event_clock);
      else if (key == "refractory")
        spec.refractory = duration(v, full);
      else if (key == "debounce")
        spec.debounce = duration(v, full);
      else
        fail(k.source(), full,
             "unknown key (name, chip, line, edges, bias, active_low, clock, refractory, debounce)");
    }
    if (spec.name.empty()) fail(table.source(), prefix, "a channel needs a name");
    if (spec.line.empty()) fail(table.source(), prefix + ".line", "a channel needs a line (offset or name)");
    return spec;
  }

  RecordConfig read(const toml::table& root) const {
    RecordConfig c;
    for (auto&& [k, v] : root) {
      const std::string key(k.str());
      if (key == "node")
        c.node = string(v, key);
      else if (key == "role")
        c.role = word(v, key, core::parse_role);
      else if (key == "scenario")
        c.scenario = string(v, key);
      else if (key == "label")
        c.label = string(v, key);
      else if (key == "source")
        c.source = word(v, key, [](const std::string& s) {
          if (s != "gpio" && s != "kmsg" && s != "sim")
            throw core::Error(core::ErrorKind::usage, fmt::format("'{}': use gpio, kmsg or sim", s));
          return s;
        });
      else if (key == "kmsg")
        c.kmsg = string(v, key);
      else if (key == "channel") {
        const auto* array = v.as_array();
        if (array == nullptr) fail(v.source(), key, "expected [[channel]] tables");
        for (std::size_t i = 0; i < array->size(); ++i) {
          const auto prefix = fmt::format("channel[{}]", i + 1);
          const auto* table = (*array)[i].as_table();
          if (table == nullptr) fail((*array)[i].source(), prefix, "expected a table");
          c.channel_keys.emplace_back();
          c.channels.push_back(channel(*table, prefix, c.channel_keys.back()));
          for (std::size_t j = 0; j + 1 < c.channels.size(); ++j)
            if (c.channels[j].name == c.channels.back().name)
              fail(table->source(), prefix + ".name",
                   fmt::format("channel '{}' is defined twice", c.channels[j].name));
        }
      } else if (key == "rt") {
        const auto* table = v.as_table();
        if (table == nullptr) fail(v.source(), key, "expected a table [rt]");
        for (auto&& [rk, rv] : *table) {
          const auto full = "rt." + std::string(rk.str());
          if (rk.str() == "priority")
            c.rt_priority = static_cast<int>(integer(rv, full, 1, 99));
          else if (rk.str() == "cpu")
            c.cpu = static_cast<int>(integer(rv, full, 0, 4095));
          else if (rk.str() == "irq_cpu")
            c.irq_cpu = static_cast<int>(integer(rv, full, 0, 4095));
          else if (rk.str() == "mlock")
            c.mlock = boolean(rv, full);
          else
            fail(rk.source(), full, "unknown key (priority, cpu, mlock, irq_cpu)");
        }
      } else if (key == "store") {
        const auto* table = v.as_table();
        if (table == nullptr) fail(v.source(), key, "expected a table [store]");
        for (auto&& [sk, sv] : *table) {
          const auto full = "store." + std::string(sk.str());
          if (sk.str() == "batch")
            c.batch = integer(sv, full, 1, 1'000'000);
          else if (sk.str() == "commit_interval")
            c.commit_interval = duration(sv, full);
          else if (sk.str() == "durability")
            c.durability = word(sv, full, [](const std::string& s) {
              if (s != "full" && s != "normal" && s != "off")
                throw core::Error(core::ErrorKind::usage, fmt::format("'{}': use full, normal or off", s));
              return s;
            });
          else
            fail(sk.source(), full, "unknown key (batch, commit_interval, durability)");
        }
      } else if (key == "clock") {
        const auto* table = v.as_table();
        if (table == nullptr) fail(v.source(), key, "expected a table [clock]");
        for (auto&& [ck, cv] : *table) {
          const auto full = "clock." + std::string(ck.str());
          if (ck.str() == "monitor")
            c.clock_monitor = boolean(cv, full);
          else if (ck.str() == "kernel_interval")
            c.kernel_interval = duration(cv, full);
          else if (ck.str() == "chrony_interval")
            c.chrony_interval = duration(cv, full);
          else if (ck.str() == "ptp_interval")
            c.ptp_interval = duration(cv, full);
          else
            fail(ck.source(), full, "unknown key (monitor, kernel_interval, chrony_interval, ptp_interval)");
        }
      } else {
        fail(k.source(), key,
             "unknown key (node, role, scenario, label, source, kmsg, [[channel]], [rt], [store], [clock])");
      }
    }
    return c;
  }

 private:
  std::string name_;
};

}  // namespace

RecordConfig parse_record_config(std::string_view text, const std::string& name) {
  toml::table root;
  try {
    root = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    throw core::Error(core::ErrorKind::data, fmt::format("{}:{}:{}: {}", name, e.source().begin.line,
                                                         e.source().begin.column, e.description()));
  }
  return Reader(name).read(root);
}

RecordConfig load_record_config(const std::string& path) {
  // Read as every input file is (formats/input_text.hpp): a device is refused, and a last line cut
  // mid-write too: "batch = 51" cut from "batch = 512" is valid TOML.
  const auto input = formats::InputText::read_file(path);
  formats::check_input(input.text(), input.name());
  return parse_record_config(input.text(), path);
}

}  // namespace m2mlat::capture
