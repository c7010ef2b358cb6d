// The one mapping between the store's clock samples and the clock records of the events files
// (formats/clock_records.hpp): the same values, the file naming the node the store keeps per session.
#pragma once

#include <string>

#include "m2mlat/formats/clock_records.hpp"
#include "m2mlat/store/records.hpp"

namespace m2mlat::analysis {

formats::ClockRecord to_clock_record(const store::ClockSample& sample, const std::string& node);
store::ClockSample to_clock_sample(const formats::ClockRecord& record);  // session_id 0

}  // namespace m2mlat::analysis
