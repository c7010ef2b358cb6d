// `m2mlat merge`: join per-board store files into a campaign store (offline path; the live path is
// `m2mlat collect`). Idempotent: a store merged again adds only what it gained since. Boards whose
// kernel logs were imported into stores of their own meet here first: a board that followed the
// other's clock step is read then (analysis/import_follow.hpp).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>

#include "m2mlat/analysis/import_follow.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/store/merge.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::cli {

namespace {

struct MergeCommand {
  std::string campaign;
  std::vector<std::string> boards;
  bool json = false;
};

// The merge itself, one transaction; printed only once it is committed.
int merge_into(const MergeCommand& c) {
  auto campaign = store::Store::open(c.campaign);
  store::WholeWrite whole(campaign);
  std::int64_t before = 0;  // the largest session id before the merge
  for (const auto& s : campaign.sessions()) before = std::max(before, s.id);
  std::vector<store::MergeResult> merged;
  for (const auto& board : c.boards) merged.push_back(store::merge_store(campaign, board));
  std::set<std::string> scenarios;
  for (const auto& s : campaign.sessions())
    if (s.id > before) scenarios.insert(s.scenario);
  const auto follow = analysis::take_over_steps(campaign, scenarios, {}, "merge");
  whole.commit();

  nlohmann::json report = nlohmann::json::array();
  for (const auto& r : merged) {
    report.push_back({{"store", r.path},
                      {"origin", r.origin},
                      {"nodes", r.nodes},
                      {"events", r.events},
                      {"clock_samples", r.clock_samples},
                      {"losses", r.losses},
                      {"rate_blocks", r.rate_blocks},
                      {"markers", r.markers}});
    if (!c.json)
      fmt::print("{} ({}): {} new events, {} clock samples, {} losses, {} raw rate blocks, {} markers\n",
                 core::printable(r.path), core::printable(fmt::format("{}", fmt::join(r.nodes, ", "))),
                 r.events, r.clock_samples, r.losses, r.rate_blocks, r.markers);
  }
  for (const auto& note : follow.notes) warn(note);
  nlohmann::json followed = nlohmann::json::array();
  for (const auto& f : follow.followed) {
    followed.push_back(analysis::to_json(f));
    if (!c.json) fmt::print("{}\n", core::printable(analysis::followed_line(f)));
  }
  if (c.json) {
    nlohmann::json doc{{"campaign", c.campaign}, {"merged", report}};
    if (!followed.empty()) doc["followed_steps"] = followed;
    print_json(doc);
  }
  return 0;
}

int run_merge(const MergeCommand& c) {
  // Every board store is checked before the campaign store is opened (or made): a missing one leaves
  // nothing behind. A campaign store the merge made goes again if it fails.
  for (const auto& board : c.boards)
    if (!std::filesystem::exists(board))
      throw core::Error(core::ErrorKind::no_input, fmt::format("{}: no such store", board));
  const bool existed = std::filesystem::exists(c.campaign);
  try {
    return merge_into(c);
  } catch (const core::Error&) {
    if (!existed) store::remove_store_files(c.campaign);
    throw;
  }
}

}  // namespace

Runner attach_merge(CLI::App& sub) {
  auto c = std::make_shared<MergeCommand>();
  sub.add_option("campaign", c->campaign, "Campaign store to merge into (created if missing)")->required();
  sub.add_option("boards", c->boards, "Board stores (from `m2mlat record`, `agent` or `import`)")->required();
  sub.add_flag("--json", c->json, "Print what was merged as JSON");
  return [c] { return run_merge(*c); };
}

}  // namespace m2mlat::cli
