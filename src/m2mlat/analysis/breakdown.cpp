#include "m2mlat/analysis/breakdown.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/stats/quantile.hpp"

namespace m2mlat::analysis {

MarkerIndex::MarkerIndex(std::span<const markers::Marker> markers) : markers_(markers), size_(markers.size()) {
  if (markers.size() > std::numeric_limits<std::uint32_t>::max())
    throw core::Error(core::ErrorKind::usage, "more than 2^32 markers: give fewer marker files");
  for (std::uint32_t i = 0; i < markers.size(); ++i) {
    const auto& m = markers[i];
    const Stamp s{m.time.ns(), i};
    by_name_[{m.node, m.name}].push_back(s);
    if (!m.key.empty()) by_key_[{m.node, m.name, m.key}].push_back(s);
  }
  for (auto& [_, v] : by_name_) std::ranges::sort(v);
  for (auto& [_, v] : by_key_) std::ranges::sort(v);
}

std::span<const MarkerIndex::Stamp> MarkerIndex::of(const std::string& node, const std::string& name) const {
  const auto it = by_name_.find({node, name});
  return it == by_name_.end() ? std::span<const Stamp>{} : std::span<const Stamp>(it->second);
}

std::span<const MarkerIndex::Stamp> MarkerIndex::of(const std::string& node, const std::string& name,
                                                    const std::string& key) const {
  const auto it = by_key_.find({node, name, key});
  return it == by_key_.end() ? std::span<const Stamp>{} : std::span<const Stamp>(it->second);
}

std::string_view to_string(StageGap gap) {
  switch (gap) {
    case StageGap::none: return "complete";
    case StageGap::missing: return "missing";
    case StageGap::out_of_order: return "out_of_order";
    case StageGap::after_effect: return "after_effect";
  }
  return "missing";
}

namespace {

// The first stamp at or after `ns` (end() when none).
const MarkerIndex::Stamp* first_at_or_after(std::span<const MarkerIndex::Stamp> v, std::int64_t ns) {
  const auto it = std::ranges::lower_bound(v, ns, {}, &MarkerIndex::Stamp::ns);
  return it == v.end() ? nullptr : &*it;
}

// The last stamp at or before `ns` (nullptr when none).
const MarkerIndex::Stamp* last_at_or_before(std::span<const MarkerIndex::Stamp> v, std::int64_t ns) {
  const auto it = std::ranges::upper_bound(v, ns, {}, &MarkerIndex::Stamp::ns);
  return it == v.begin() ? nullptr : &*(it - 1);
}

}  // namespace

EventStages event_stages(std::int64_t cause, std::int64_t effect, core::Clock clock, const StageRule& rule,
                         const MarkerIndex& index) {
  if (clock != core::Clock::realtime)
    throw core::Error(core::ErrorKind::data,
                      fmt::format("the events are on {}, the markers on realtime: a breakdown needs the "
                                  "boards' CLOCK_REALTIME events",
                                  core::to_string(clock)));
  EventStages e;
  e.cause_time = core::TimePoint::from_ns(clock, cause);
  e.effect_time = core::TimePoint::from_ns(clock, effect);
  e.m2m_ns = effect - cause;
  std::int64_t previous = cause;
  const markers::Marker* previous_marker = nullptr;
  for (std::size_t k = 0; k < rule.stages.size(); ++k) {
    const auto& sel = rule.stages[k].end;
    auto stop = [&](StageGap gap, std::string detail) {
      e.gap = gap;
      e.gap_stage = k;
      e.detail = std::move(detail);
    };
    const MarkerIndex::Stamp* found = nullptr;
    switch (sel.kind) {
      case SelectorKind::effect:
        e.stage_ns.push_back(effect - previous);
        return e;
      case SelectorKind::first_after_cause:
      case SelectorKind::first_after_previous: {
        const std::int64_t from = sel.kind == SelectorKind::first_after_cause ? cause : previous;
        found = first_at_or_after(index.of(sel.node, sel.name), from);
        if (found == nullptr) {
          stop(StageGap::missing, fmt::format("no {}:{} after the {}", core::printable(sel.node),
                                              core::printable(sel.name),
                                              sel.kind == SelectorKind::first_after_cause ? "cause" : "previous stage"));
          return e;
        }
        break;
      }
      case SelectorKind::last_before_effect:
        found = last_at_or_before(index.of(sel.node, sel.name), effect);
        if (found == nullptr) {
          stop(StageGap::missing,
               fmt::format("no {}:{} before the effect", core::printable(sel.node), core::printable(sel.name)));
          return e;
        }
        break;
      case SelectorKind::same_key: {
        const auto v = index.of(sel.node, sel.name, previous_marker->key);
        if (v.empty()) {
          stop(StageGap::missing, fmt::format("no {}:{} with key {}", core::printable(sel.node),
                                              core::printable(sel.name), core::printable(previous_marker->key)));
          return e;
        }
        // A key seen again later (a counter that wrapped, a resent command): the first one not
        // before the previous stage's end; if all are before it, the last of them shows the disorder.
        found = first_at_or_after(v, previous);
        if (found == nullptr) found = &v.back();
        break;
      }
    }
    const auto& m = index.marker(found->marker);
    if (found->ns < previous) {
      stop(StageGap::out_of_order,
           fmt::format("{}:{} (key {}) at {} ns, before the previous stage's end at {} ns", core::printable(m.node),
                       core::printable(m.name), core::printable(m.key), found->ns, previous));
      return e;
    }
    if (found->ns > effect) {
      stop(StageGap::after_effect, fmt::format("{}:{} (key {}) at {} ns, after the effect at {} ns",
                                               core::printable(m.node), core::printable(m.name),
                                               core::printable(m.key), found->ns, effect));
      return e;
    }
    e.stage_ns.push_back(found->ns - previous);
    previous = found->ns;
    previous_marker = &m;
  }
  return e;  // not reached: a parsed rule ends at `effect`
}

Breakdown break_down(std::span<const std::int64_t> cause_ns, std::span<const std::int64_t> effect_ns,
                     core::Clock clock, std::span<const std::size_t> positions,
                     std::span<const std::int64_t> cause_ids, const StageRule& rule,
                     const MarkerIndex& index) {
  std::vector<EventStages> events;
  events.reserve(cause_ns.size());
  for (std::size_t i = 0; i < cause_ns.size(); ++i) {
    auto e = event_stages(cause_ns[i], effect_ns[i], clock, rule, index);
    e.pair = positions[i];
    e.cause_id = cause_ids[i];
    events.push_back(std::move(e));
  }
  return summarize_stages(std::move(events), rule);
}

Breakdown summarize_stages(std::vector<EventStages> events, const StageRule& rule) {
  Breakdown b;
  const std::size_t n_stages = rule.stages.size();
  std::vector<std::vector<std::int64_t>> columns(n_stages);
  std::vector<std::int64_t> m2m;
  std::vector<std::size_t> gap_counts(n_stages * 4, 0);
  b.events.reserve(events.size());
  for (auto& e : events) {
    if (e.complete()) {
      ++b.complete;
      for (std::size_t k = 0; k < n_stages; ++k) columns[k].push_back(e.stage_ns[k]);
      m2m.push_back(e.m2m_ns);
    } else {
      ++b.incomplete;
      ++gap_counts[e.gap_stage * 4 + static_cast<std::size_t>(e.gap)];
    }
    b.events.push_back(std::move(e));
  }
  // Exact sums (int64 ns: 2^63 ns is 292 years of latency in total) for the shares and the means.
  std::int64_t m2m_sum = 0;
  for (const auto v : m2m) m2m_sum += v;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::ranges::sort(m2m);
  b.m2m_median_ns = m2m.empty() ? nan : stats::quantile(m2m, 0.5);
  b.m2m_mean_ns = m2m.empty() ? nan : static_cast<double>(m2m_sum) / static_cast<double>(m2m.size());
  for (std::size_t k = 0; k < n_stages; ++k) {
    auto& c = columns[k];
    StageStats s;
    s.name = rule.stages[k].name;
    s.selector = to_string(rule.stages[k].end);
    std::int64_t sum = 0;
    for (const auto v : c) sum += v;
    std::ranges::sort(c);
    if (c.empty()) {
      s.median_ns = s.q1_ns = s.q3_ns = s.mean_ns = s.share = nan;
    } else {
      s.median_ns = stats::quantile(c, 0.5);
      s.q1_ns = stats::quantile(c, 0.25);
      s.q3_ns = stats::quantile(c, 0.75);
      s.mean_ns = static_cast<double>(sum) / static_cast<double>(c.size());
      s.min_ns = c.front();
      s.max_ns = c.back();
      s.share = m2m_sum == 0 ? nan : static_cast<double>(sum) / static_cast<double>(m2m_sum);
    }
    b.stages.push_back(std::move(s));
    for (std::size_t g = 1; g < 4; ++g)
      if (const auto count = gap_counts[k * 4 + g]; count > 0)
        b.gaps.push_back({rule.stages[k].name, static_cast<StageGap>(g), count});
  }
  return b;
}

}  // namespace m2mlat::analysis
