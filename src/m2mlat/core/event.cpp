// Names of edges and roles, and "node/channel" references.
#include "m2mlat/core/event.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"

namespace m2mlat::core {

std::string_view to_string(Edge edge) { return edge == Edge::rising ? "rising" : "falling"; }

Edge parse_edge(std::string_view text) {
  if (text == "rising") return Edge::rising;
  if (text == "falling") return Edge::falling;
  throw Error(ErrorKind::usage, fmt::format("unknown edge '{}' (expected rising or falling)", text));
}

std::string_view to_string(Role role) {
  switch (role) {
    case Role::cause: return "cause";
    case Role::effect: return "effect";
    case Role::observer: return "observer";
  }
  return "observer";
}

Role parse_role(std::string_view text) {
  if (text == "cause" || text == "operator" || text == "remote") return Role::cause;
  if (text == "effect" || text == "vehicle") return Role::effect;
  if (text == "observer") return Role::observer;
  throw Error(ErrorKind::usage,
              fmt::format("unknown role '{}' (expected cause/operator, effect/vehicle or observer)", text));
}

ChannelRef parse_channel_ref(std::string_view text, std::string_view default_channel) {
  const auto slash = text.find('/');
  ChannelRef ref{std::string(text.substr(0, slash)),
                 std::string(slash == std::string_view::npos ? default_channel : text.substr(slash + 1))};
  if (ref.node.empty() || (slash != std::string_view::npos && ref.channel.empty()))
    throw Error(ErrorKind::usage, fmt::format("'{}' is not a channel (expected node/channel)", text));
  return ref;
}

std::string to_string(const ChannelRef& ref) { return ref.node + "/" + ref.channel; }

}  // namespace m2mlat::core
