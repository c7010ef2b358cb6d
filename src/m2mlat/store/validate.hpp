// Checks of values before they are written, so that bad input gets a message naming the field and
// changes nothing stored. The schema's CHECK constraints are the second line of defence.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "m2mlat/core/event.hpp"
#include "m2mlat/store/records.hpp"

namespace m2mlat::store::validate {

// Throws core::Error(data) "<what>: field 'field' is not valid JSON: <parser's message>".
void json(const std::string& store_path, std::string_view what, std::string_view field,
          const std::string& text);

// `store_path` names the store; `index` is the position in the batch (0-based) for messages.
void session(const std::string& store_path, const Session& session);
void event(const std::string& store_path, std::size_t index, const core::Event& event);
void clock_sample(const std::string& store_path, std::size_t index, const ClockSample& sample);
void loss(const std::string& store_path, std::size_t index, const Loss& loss);
// A channel name, a known clock, a positive finite scale, 1 to rate_block::kMaxSamples samples in
// time order with non-negative bounds.
void rate_block(const std::string& store_path, std::size_t index, const RateBlock& block);
// A name, a known clock, a source of lower-case letters, digits and '_', a non-negative uncertainty.
void marker(const std::string& store_path, std::size_t index, const MarkerRecord& marker);

}  // namespace m2mlat::store::validate
