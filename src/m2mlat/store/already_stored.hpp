// Events a store holds already: an import of a file given twice (or of a copy) must not store its
// events again, where they would be read as bounces of themselves.
#pragma once

#include <span>
#include <vector>

#include "m2mlat/core/event.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::store {

// Per event of `events` (one node): whether the store holds an event of the same node, channel,
// edge and time (to the ns, on the same clock) in any session. Two real edges never share a ns stamp.
std::vector<bool> already_stored(const Store& store, std::span<const core::Event> events);

}  // namespace m2mlat::store
