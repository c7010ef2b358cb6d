// Fuzzes the wire decoders (net/wire.hpp) as a coordinator meets them: bytes from an agent parsed as
// JSON, then decoded as a session, event, clock sample, loss or status (the first byte chooses).
// Decoding either refuses with core::Error(data) or gives a value that encodes and decodes back to
// itself. The canonical event reader (parse_canonical_event) sees the raw bytes first: whatever it
// takes, the JSON decoder must take too and give the same event.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "m2mlat/core/error.hpp"
#include "m2mlat/net/wire.hpp"

namespace {
template <typename Decode>
void round_trip(const nlohmann::json& json, Decode decode) {
  try {
    const auto value = decode(json);
    if (!(decode(nlohmann::json::parse(m2mlat::net::to_json(value).dump())) == value)) std::abort();
  } catch (const m2mlat::core::Error& e) {
    if (e.kind() != m2mlat::core::ErrorKind::data) std::abort();
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  using namespace m2mlat;
  const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (auto fast = net::parse_canonical_event(text)) {
    // The text is canonical: it is valid JSON that the field-by-field decoder accepts as the same.
    const auto slow = net::event_from_json(nlohmann::json::parse(text), "fuzz", "", core::Role::cause);
    if (!(slow.event == fast->event && slow.seq == fast->seq && slow.session_id == fast->session_id))
      std::abort();
  }
  const auto json = nlohmann::json::parse(data + 1, data + size, nullptr, false);
  if (json.is_discarded()) return 0;
  switch (data[0] % 5) {
    case 0:
      round_trip(json, [](const nlohmann::json& j) { return net::session_from_json(j, "fuzz"); });
      break;
    case 1:
      round_trip(json, [](const nlohmann::json& j) {
        return net::event_from_json(j, "fuzz", "n", core::Role::cause);
      });
      break;
    case 2:
      round_trip(json, [](const nlohmann::json& j) { return net::clock_sample_from_json(j, "fuzz"); });
      break;
    case 3: round_trip(json, [](const nlohmann::json& j) { return net::loss_from_json(j, "fuzz"); }); break;
    default:
      round_trip(json, [](const nlohmann::json& j) { return net::status_from_json(j, "fuzz"); });
      break;
  }
  return 0;
}
