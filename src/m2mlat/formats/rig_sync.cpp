// Reading the reference rig's synchronisation-test CSV.
#include "m2mlat/formats/rig_sync.hpp"

#include "m2mlat/formats/fixed_csv.hpp"

namespace m2mlat::formats {

namespace {
enum SyncColumn : std::size_t {
  kSyncTrigger = 0,
  kSyncOffsetNs = 1,
  kSyncJitterNs = 2,
  kSyncEmpty = 3,
  kSyncOffsetMs = 4,
  kSyncJitterMs = 5
};
}  // namespace

SyncImport import_rig_sync_csv(std::string_view text, std::string_view name) {
  FixedCsv csv(text, name, kRigSyncColumns);
  SyncImport result;
  while (csv.next()) {
    SyncSample sample;
    sample.line = csv.line();
    sample.trigger_time = core::Duration{csv.decimal_seconds(kSyncTrigger)};
    sample.offset_ns = csv.int64(kSyncOffsetNs);
    sample.jitter_ns = csv.int64(kSyncJitterNs);
    csv.expect_empty(kSyncEmpty);
    (void)csv.decimal_ms(kSyncOffsetMs);  // redundant magnitudes: only checked to be numbers
    (void)csv.decimal_ms(kSyncJitterMs);
    result.samples.push_back(sample);
  }
  return result;
}

}  // namespace m2mlat::formats
