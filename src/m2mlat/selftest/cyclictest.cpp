// Parsing cyclictest's JSON and histogram output, and running it.
#include "m2mlat/selftest/cyclictest.hpp"

#include <fmt/format.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "m2mlat/core/number.hpp"

namespace m2mlat::selftest {

namespace {

using nlohmann::json;

[[noreturn]] void fail(const core::Location& where, const std::string& what) {
  core::throw_data_error(where, what);
}

const json& member(const json& object, const char* key, const core::Location& where,
                   const std::string& path) {
  if (!object.is_object() || !object.contains(key)) fail(where, fmt::format("no field '{}{}'", path, key));
  return object.at(key);
}

std::int64_t integer(const json& object, const char* key, const core::Location& where,
                     const std::string& path) {
  const json& v = member(object, key, where, path);
  if (!v.is_number_integer()) fail(where, fmt::format("field '{}{}' is not an integer", path, key));
  return v.get<std::int64_t>();
}

std::uint64_t count(const json& object, const char* key, const core::Location& where,
                    const std::string& path) {
  const std::int64_t v = integer(object, key, where, path);
  if (v < 0) fail(where, fmt::format("field '{}{}' is negative", path, key));
  return static_cast<std::uint64_t>(v);
}

std::string string_or_empty(const json& object, const char* key) {
  return object.is_object() && object.contains(key) && object.at(key).is_string()
             ? object.at(key).get<std::string>()
             : std::string();
}

std::vector<std::string_view> words(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < s.size() && s[i] != ' ' && s[i] != '\t' && s[i] != '\r') ++i;
    if (i > start) out.push_back(s.substr(start, i - start));
  }
  return out;
}

}  // namespace

CyclictestResult parse_cyclictest_json(std::string_view text, const core::Location& where) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {  // parse_error, or out_of_range for a number like 1e999
    fail(where, std::string("not JSON: ") + e.what());
  }
  if (!doc.is_object()) fail(where, "not a JSON object");
  if (integer(doc, "file_version", where, "") != 1)
    fail(where, "field 'file_version': only version 1 is known");
  CyclictestResult r;
  r.version = string_or_empty(doc, "rt_test_version:");
  r.cmdline = string_or_empty(doc, "cmdline:");
  r.start_time = string_or_empty(doc, "start_time");
  r.end_time = string_or_empty(doc, "end_time");
  r.return_code = static_cast<int>(integer(doc, "return_code", where, ""));
  if (doc.contains("sysinfo") && doc["sysinfo"].is_object()) {
    r.kernel_release = string_or_empty(doc["sysinfo"], "release");
    const auto& rt = doc["sysinfo"];
    r.realtime_kernel =
        rt.contains("realtime") && rt["realtime"].is_number_integer() && rt["realtime"].get<int>() != 0;
  }
  const std::int64_t n = integer(doc, "num_threads", where, "");
  if (n < 1 || n > 4096) fail(where, "field 'num_threads' is out of range");
  const json& threads = member(doc, "thread", where, "");
  for (std::int64_t i = 0; i < n; ++i) {
    const std::string key = std::to_string(i);
    const std::string path = "thread." + key + ".";
    const json& t = member(threads, key.c_str(), where, "thread.");
    CyclictestThread th;
    th.cpu = static_cast<int>(integer(t, "cpu", where, path));
    th.cycles = count(t, "cycles", where, path);
    th.min_us = integer(t, "min", where, path);
    th.max_us = integer(t, "max", where, path);
    const json& avg = member(t, "avg", where, path);
    if (!avg.is_number()) fail(where, fmt::format("field '{}avg' is not a number", path));
    th.avg_us = avg.get<double>();
    std::uint64_t in_histogram = 0;
    if (t.contains("histogram")) {
      const json& h = t.at("histogram");
      if (!h.is_object()) fail(where, fmt::format("field '{}histogram' is not an object", path));
      for (const auto& [bucket, c] : h.items()) {
        std::int64_t us = 0;
        if (!core::parse_integer(bucket, us) || us < 0)
          fail(where, fmt::format("field '{}histogram': bucket '{}' is not a number of us", path, bucket));
        if (!c.is_number_integer() || c.get<std::int64_t>() < 0)
          fail(where, fmt::format("field '{}histogram.{}' is not a count", path, bucket));
        const auto v = c.get<std::uint64_t>();
        if (v > 0) th.histogram.emplace_back(us, v);
        in_histogram += v;
      }
      std::sort(th.histogram.begin(), th.histogram.end());
      if (in_histogram > th.cycles)
        fail(where, fmt::format("{}histogram holds {} wake-ups, more than the {} cycles", path, in_histogram,
                                th.cycles));
      th.overflows = th.cycles - in_histogram;
    }
    if (th.cycles > 0 && (th.min_us > th.max_us || th.min_us < 0))
      fail(where, fmt::format("{}min/max: {} > {} or negative", path, th.min_us, th.max_us));
    r.threads.push_back(std::move(th));
  }
  return r;
}

CyclictestHistogram parse_cyclictest_histogram(std::string_view text, const core::Location& where) {
  CyclictestHistogram h;
  core::Location at = where;
  at.line = 0;
  std::size_t threads = 0;
  auto summary = [&](std::string_view rest, auto& into) {
    const auto w = words(rest);
    if (threads == 0) threads = w.size();
    if (w.size() != threads)
      fail(at, fmt::format("{} values, expected one per thread ({})", w.size(), threads));
    into.clear();
    for (const auto v : w) {
      std::uint64_t x = 0;
      if (!core::parse_integer(v, x)) fail(at, fmt::format("'{}' is not a number", v));
      into.push_back(static_cast<typename std::decay_t<decltype(into)>::value_type>(x));
    }
  };
  std::int64_t expected_bucket = 0;
  while (!text.empty()) {
    const auto nl = text.find('\n');
    const std::string_view line = text.substr(0, nl);
    text.remove_prefix(nl == std::string_view::npos ? text.size() : nl + 1);
    ++at.line;
    if (line.empty()) continue;
    if (line.front() == '#') {
      const auto colon = line.find(':');
      const std::string_view label = line.substr(0, colon);
      const std::string_view rest =
          colon == std::string_view::npos ? std::string_view{} : line.substr(colon + 1);
      if (label == "# Total")
        summary(rest, h.total);
      else if (label == "# Min Latencies")
        summary(rest, h.min_us);
      else if (label == "# Avg Latencies")
        summary(rest, h.avg_us);
      else if (label == "# Max Latencies")
        summary(rest, h.max_us);
      else if (label == "# Histogram Overflows")
        summary(rest, h.overflows);
      continue;  // other comments: "# Histogram", "# Thread N: <cycle numbers>", cpu_dma_latency
    }
    const auto w = words(line);
    if (w.empty()) continue;
    std::uint64_t bucket = 0;
    if (!core::parse_integer(w[0], bucket)) fail(at, fmt::format("'{}' is not a histogram bucket", w[0]));
    if (static_cast<std::int64_t>(bucket) != expected_bucket)
      fail(at, fmt::format("bucket {} where {} was expected", bucket, expected_bucket));
    ++expected_bucket;
    if (threads == 0) {
      threads = w.size() - 1;
      if (threads == 0) fail(at, "a bucket without counts");
    }
    if (h.counts.empty()) h.counts.resize(threads);
    if (w.size() - 1 != threads) fail(at, fmt::format("{} counts, expected {}", w.size() - 1, threads));
    for (std::size_t t = 0; t < threads; ++t) {
      std::uint64_t c = 0;
      if (!core::parse_integer(w[t + 1], c)) fail(at, fmt::format("'{}' is not a count", w[t + 1]));
      h.counts[t].push_back(c);
    }
  }
  at.line = 0;
  if (h.counts.empty()) fail(at, "no histogram lines");
  if (h.total.size() != threads || h.overflows.size() != threads || h.min_us.size() != threads ||
      h.max_us.size() != threads)
    fail(at, "the summary lines (# Total, # Min/Max Latencies, # Histogram Overflows) are missing");
  for (std::size_t t = 0; t < threads; ++t) {
    std::uint64_t sum = 0;
    for (const auto c : h.counts[t]) sum += c;
    if (sum != h.total[t])
      fail(at, fmt::format("thread {}: buckets add up to {}, # Total says {}", t, sum, h.total[t]));
  }
  return h;
}

std::vector<std::string> cyclictest_argv(const CyclictestOptions& o, const std::string& json_path) {
  const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(o.duration).count();
  return {o.program,
          "--mlockall",
          fmt::format("--priority={}", o.priority),
          fmt::format("--affinity={}", o.cpu),
          "--threads=1",
          fmt::format("--interval={}", o.interval_us),
          fmt::format("--duration={}s", seconds),
          fmt::format("--histogram={}", o.histogram_us),
          "--json=" + json_path,
          "-q"};
}

CyclictestResult run_cyclictest(process::CommandRunner& runner, const CyclictestOptions& o) {
  if (o.cpu < 0) throw core::Error(core::ErrorKind::usage, "the core must be >= 0");
  if (o.priority < 1 || o.priority > 99)
    throw core::Error(core::ErrorKind::usage, "the priority must be 1..99");
  if (o.interval_us < 50) throw core::Error(core::ErrorKind::usage, "the interval must be at least 50 us");
  if (o.histogram_us < 1 || o.histogram_us > 100000)
    throw core::Error(core::ErrorKind::usage, "the histogram range must be 1..100000 us");
  if (o.duration < std::chrono::seconds(1))
    throw core::Error(core::ErrorKind::usage, "the duration must be >= 1 s");

  char dir_template[] = "/tmp/m2mlat-cyclictest-XXXXXX";
  if (!::mkdtemp(dir_template))
    throw core::Error(core::ErrorKind::io, "cannot create a temporary directory in /tmp");
  const std::string dir = dir_template;
  const std::string json_path = dir + "/cyclictest.json";
  const auto argv = cyclictest_argv(o, json_path);
  const auto result = runner.run(argv, o.duration + std::chrono::seconds(30));
  std::string json_text;
  {
    std::ifstream in(json_path);
    std::ostringstream s;
    s << in.rdbuf();
    json_text = s.str();
  }
  ::unlink(json_path.c_str());
  ::rmdir(dir.c_str());
  if (!result.ok()) throw process::command_error(argv, result);
  CyclictestResult r = parse_cyclictest_json(json_text, core::Location{"cyclictest --json output", 0});
  const CyclictestHistogram h =
      parse_cyclictest_histogram(result.out, core::Location{"cyclictest histogram", 0});
  if (h.counts.size() != r.threads.size())
    throw core::Error(core::ErrorKind::data,
                      "cyclictest: the histogram and the JSON disagree on the thread count");
  for (std::size_t t = 0; t < r.threads.size(); ++t) {
    if (h.total[t] + h.overflows[t] != r.threads[t].cycles || h.overflows[t] != r.threads[t].overflows)
      throw core::Error(
          core::ErrorKind::data,
          fmt::format("cyclictest thread {}: the histogram ({} + {} overflows) and the JSON ({} cycles) "
                      "disagree",
                      t, h.total[t], h.overflows[t], r.threads[t].cycles));
  }
  return r;
}

}  // namespace m2mlat::selftest
