// Reading the reference rig's synchronisation-test CSV.
#include "m2mlat/formats/rig_sync.hpp"

#include "m2mlat/formats/fixed_csv.hpp"

namespace m2mlat::formats {

namespace {
enum Column : std::size_t {
  kTrigger = 0,
  kOffsetNs = 1,
  kJitterNs = 2,
  kEmpty = 3,
  kOffsetMs = 4,
  kJitterMs = 5
};
}  // namespace

SyncImport import_rig_sync_csv(std::string_view text, std::string_view name) {
  FixedCsv csv(text, name, kRigSyncColumns);
  SyncImport result;
  while (csv.next()) {
    SyncSample sample;
    sample.line = csv.line();
    sample.trigger_time = core::Duration{csv.decimal_seconds(kTrigger)};
    sample.offset_ns = csv.int64(kOffsetNs);
    sample.jitter_ns = csv.int64(kJitterNs);
    csv.expect_empty(kEmpty);
    (void)csv.decimal_ms(kOffsetMs);  // redundant magnitudes: only checked to be numbers
    (void)csv.decimal_ms(kJitterMs);
    result.samples.push_back(sample);
  }
  return result;
}

}  // namespace m2mlat::formats
