// The agent's counters in the Prometheus text exposition format, version 0.0.4 (GET /metrics), so
// that a rig's boards can be watched with the usual tools. Made from the same Status as
// GET /v1/status, plus what the HTTP server did with its connections; times are written as exact
// decimal seconds (no float rounding of nanoseconds).
#pragma once

#include <string>
#include <string_view>

#include "m2mlat/net/http_server.hpp"
#include "m2mlat/net/wire.hpp"

namespace m2mlat::net {

inline constexpr std::string_view kMetricsContentType = "text/plain; version=0.0.4; charset=utf-8";

std::string render_metrics(const Status& status, const ConnectionCounts& connections = {});

// A label value with backslash, double quote and newline escaped as the format requires.
std::string escape_label(std::string_view value);

}  // namespace m2mlat::net
