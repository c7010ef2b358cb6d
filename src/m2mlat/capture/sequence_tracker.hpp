// Gap detection in a kernel sequence number: the request's seqno, a line's line_seqno, or the kmsg
// record number. Each number the counter skips is an event (or record) the kernel produced and the
// reader never got, e.g. because the request's buffer overflowed and the kernel dropped the oldest.
#pragma once

#include <cstdint>
#include <optional>

namespace m2mlat::capture {

class SequenceTracker {
 public:
  struct Missing {
    std::uint64_t first = 0;  // the first number skipped
    std::uint64_t count = 0;  // how many were skipped
  };

  // first_expected: the number the first observed value should have (1 for a fresh GPIO request,
  // whose counters start at 1); 0 = the first observed value starts the sequence (kmsg, joined in
  // the middle). wrap_bits: the counter's width (32 for the uAPI's __u32 seqno; 64 for kmsg).
  explicit SequenceTracker(std::uint64_t first_expected = 1, unsigned wrap_bits = 32);

  // The numbers skipped before `value`, if any. A value at or before the last one (a repeat, or the
  // counter going backwards) is no gap and restarts the sequence after it.
  std::optional<Missing> observe(std::uint64_t value);
  std::uint64_t missing_total() const { return missing_total_; }
  std::optional<std::uint64_t> last() const { return last_; }

 private:
  std::uint64_t expected_;
  std::uint64_t mask_;  // counter width mask
  std::optional<std::uint64_t> last_;
  std::uint64_t missing_total_ = 0;
};

}  // namespace m2mlat::capture
