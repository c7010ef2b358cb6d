#include "m2mlat/formats/rate_trace_csv.hpp"

#include <fmt/format.h>

#include <charconv>
#include <limits>

#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/fields.hpp"
#include "m2mlat/formats/input_text.hpp"

namespace m2mlat::formats {

namespace {

constexpr std::string_view kHeader = "time_ns,bound_ns,x,y,z";
constexpr std::string_view kFieldNames[] = {"time_ns", "bound_ns", "x", "y", "z"};

std::int64_t require_range(std::string_view file, long line, std::string_view field, std::string_view text,
                           std::int64_t low, std::int64_t high) {
  const std::int64_t value = require_int64(file, line, field, text);
  if (value < low || value > high)
    throw_field_error(file, line, field, text, fmt::format("is out of range [{}, {}]", low, high));
  return value;
}

}  // namespace

void write_rate_trace_csv(std::ostream& out, const core::RateTrace& trace,
                          const std::vector<std::string>& comments) {
  fmt::memory_buffer buffer;
  fmt::format_to(std::back_inserter(buffer), "# format: {}\n# clock: {}\n# counts_per_deg_s: {}\n",
                 kRateTraceFormat, core::to_string(trace.clock), trace.counts_per_deg_s);
  for (const auto& c : comments) {
    if (c.find_first_of("\r\n") != std::string::npos)
      throw core::Error(core::ErrorKind::internal, "a gyroscope trace comment with a line break");
    fmt::format_to(std::back_inserter(buffer), "# {}\n", c);
  }
  fmt::format_to(std::back_inserter(buffer), "{}\n", kHeader);
  for (const auto& s : trace.samples) {
    fmt::format_to(std::back_inserter(buffer), "{},{},{},{},{}\n", s.time_ns, s.bound_ns, s.raw[0], s.raw[1],
                   s.raw[2]);
    if (buffer.size() > 1 << 16) {
      out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      buffer.clear();
    }
  }
  out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
}

core::RateTrace read_rate_trace_csv(std::string_view text, std::string_view name) {
  check_input(text, name);
  core::RateTrace trace;
  LineReader lines(text);
  std::string_view line;
  bool format_seen = false, header_seen = false;
  std::vector<std::string_view> fields;
  while (lines.next(line)) {
    const long n = lines.line_number();
    if (!header_seen) {
      if (trim(line).empty()) continue;
      if (!format_seen) {
        if (line != fmt::format("# format: {}", kRateTraceFormat))
          throw_line_error(name, n,
                           fmt::format("expected the line '# format: {}' first, found {}", kRateTraceFormat,
                                       quote_for_message(line)));
        format_seen = true;
      } else if (line.starts_with("# clock:")) {
        try {
          trace.clock = core::parse_clock(trim(line.substr(8)));
        } catch (const core::Error&) {
          throw_field_error(name, n, "clock", trim(line.substr(8)), "is not a clock name");
        }
      } else if (line.starts_with("# counts_per_deg_s:")) {
        const auto value = trim(line.substr(19));
        double scale = 0;
        const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), scale);
        if (ec != std::errc{} || end != value.data() + value.size() || !(scale > 0))
          throw_field_error(name, n, "counts_per_deg_s", value, "is not a positive number");
        trace.counts_per_deg_s = scale;
      } else if (line.starts_with("#")) {
        continue;  // a comment
      } else if (line != kHeader) {
        throw_line_error(name, n,
                         fmt::format("expected the header '{}', found {}", kHeader, quote_for_message(line)));
      } else {
        header_seen = true;
      }
      continue;
    }
    if (line.empty()) continue;
    if (!split_csv(line, fields) || fields.size() != 5)
      throw_line_error(name, n,
                       fmt::format("expected 5 fields ({}), found {}", kHeader, quote_for_message(line)));
    core::RateSample s;
    s.time_ns = require_int64(name, n, kFieldNames[0], fields[0]);
    s.bound_ns = static_cast<std::int32_t>(
        require_range(name, n, kFieldNames[1], fields[1], 0, std::numeric_limits<std::int32_t>::max()));
    for (std::size_t axis = 0; axis < 3; ++axis)
      s.raw[axis] = static_cast<std::int16_t>(require_range(name, n, kFieldNames[2 + axis], fields[2 + axis],
                                                            std::numeric_limits<std::int16_t>::min(),
                                                            std::numeric_limits<std::int16_t>::max()));
    if (!trace.samples.empty() && s.time_ns < trace.samples.back().time_ns)
      throw_field_error(name, n, "time_ns", fields[0], "is before the previous line's time");
    trace.samples.push_back(s);
  }
  if (!header_seen)
    throw_line_error(name, 0,
                     format_seen ? fmt::format("no header line '{}'", kHeader)
                                 : fmt::format("empty: no '# format: {}' line", kRateTraceFormat));
  return trace;
}

}  // namespace m2mlat::formats
