// The offline pipeline on real files: a store's scenarios come back analysed with their boards'
// record (no second look at the store needed), an events file and a kernel-log pair of files give
// the same pairs as the steps called by hand, and bad inputs fail with the kind the CLI maps.
#include "m2mlat/analysis/pipeline.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include <fstream>
#include <tuple>

#include "m2mlat/analysis/board_record.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/store/store.hpp"
#include "store_fixture.hpp"

namespace m2mlat::analysis::pipeline_test {
namespace {
using namespace fixture;

class PipelineTest : public StoreTest {
 protected:
  // Two scenarios of 20 manoeuvres 4 s apart, latency 800 ms + i ms; clock samples on both boards.
  std::string make_store() const {
    const auto path = file("campaign.db");
    auto s = store::Store::open(path);
    for (const std::string scenario : {"first", "second"}) {
      std::vector<core::Event> causes, effects;
      for (std::int64_t i = 0; i < 20; ++i) {
        causes.push_back(edge("operator", "wheel", kT0 + i * 4000 * kMs));
        effects.push_back(edge("vehicle", "wheel", kT0 + i * 4000 * kMs + (800 + i) * kMs));
      }
      for (const auto& [node, role, events] : {std::tuple{"operator", core::Role::cause, causes},
                                               std::tuple{"vehicle", core::Role::effect, effects}}) {
        const auto id = add_session(s, scenario, node, role, events);
        store::ClockSample c;
        c.session_id = id;
        c.time = rt(kT0);
        c.source = "chrony";
        c.max_error_ns = 250'000;
        c.est_error_ns = 50'000;
        c.synchronised = true;
        s.append_clock_samples(std::vector{c});
      }
    }
    return path;
  }
};

core::ErrorKind kind_of(const analysis::PipelineInputs& inputs) {
  try {
    analysis::analyse_inputs(inputs, {});
  } catch (const core::Error& e) {
    return e.kind();
  }
  ADD_FAILURE() << "no error";
  return core::ErrorKind::internal;
}
}  // namespace

TEST_F(PipelineTest, StoreScenariosComeBackWithTheirBoardsRecord) {
  const auto path = make_store();
  analysis::PipelineInputs inputs;
  inputs.inputs = {path};
  const auto all = analysis::analyse_inputs(inputs, {});
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].input.scenario, "first");
  EXPECT_EQ(all[1].input.scenario, "second");

  inputs.scenarios = {"second"};
  analysis::PipelineOptions options;
  options.uncertainty.kernel_max = core::Duration{20'000};
  const auto only = analysis::analyse_inputs(inputs, options);
  ASSERT_EQ(only.size(), 1u);
  const auto& r = only.front();

  // The same as the steps by hand.
  store::Options read;
  read.read_only = true;
  const auto s = store::Store::open(path, read);
  auto expected = analysis::analyse(analysis::load_scenario(s, "second", {}), {}, {});
  analysis::attach_board_record(expected, s, options.uncertainty, {});
  EXPECT_EQ(r.match.pairs.size(), 20u);
  EXPECT_EQ(r.match.pairs.size(), expected.match.pairs.size());
  EXPECT_DOUBLE_EQ(r.summary.median_ms, expected.summary.median_ms);
  EXPECT_EQ(r.uncertainty, expected.uncertainty);
  ASSERT_EQ(r.clocks.size(), 2u);
  EXPECT_EQ(r.clocks[0].max_error_ns, expected.clocks[0].max_error_ns);
  EXPECT_EQ(r.cause_clock_ms, expected.cause_clock_ms);
  ASSERT_EQ(r.uncertainty.size(), 20u);
  EXPECT_TRUE(r.uncertainty.front().bounded());
  EXPECT_GE(r.uncertainty.front().max_error_ns, 250'000 + 250'000 + 20'000);
}

TEST_F(PipelineTest, DataFilesGiveTheSamePairsAsTheStepsByHand) {
  // One events file with both sides, named after the file.
  std::vector<core::Event> events;
  for (std::int64_t i = 0; i < 10; ++i) {
    events.push_back(edge("operator", "wheel", kT0 + i * 4000 * kMs));
    events.push_back(edge("vehicle", "wheel", kT0 + i * 4000 * kMs + 900 * kMs));
  }
  formats::export_events(file("drive.csv"), formats::Format::events_csv, events);
  analysis::PipelineInputs inputs;
  inputs.inputs = {file("drive.csv")};
  const auto r = analysis::analyse_inputs(inputs, {});
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].input.scenario, "drive");
  EXPECT_EQ(r[0].match.pairs.size(), 10u);
  EXPECT_DOUBLE_EQ(r[0].summary.median_ms, 900.0);
  EXPECT_TRUE(r[0].uncertainty.empty());  // a data file carries no clock samples
  EXPECT_TRUE(r[0].clocks.empty());

  // A cause kernel log and an effect kernel log: the lean path (timestamps only).
  {
    std::ofstream cause(file("cause.log")), effect(file("effect.log"));
    for (std::int64_t i = 0; i < 10; ++i) {
      cause << "GPIO_17_IRQ:" << kT0 + i * 4000 * kMs << "\n";
      effect << "GPIO_27_IRQ:" << kT0 + i * 4000 * kMs + 750 * kMs << "\n";
    }
  }
  analysis::PipelineInputs logs;
  logs.cause_file = file("cause.log");
  logs.effect_file = file("effect.log");
  const auto l = analysis::analyse_inputs(logs, {});
  ASSERT_EQ(l.size(), 1u);
  // The scenario is the folder of both files; each side's node is its file's name.
  EXPECT_EQ(l[0].input.scenario, std::filesystem::path(file("cause.log")).parent_path().filename().string());
  EXPECT_EQ(l[0].input.cause_ref, (core::ChannelRef{"cause", "gpio17"}));
  EXPECT_EQ(l[0].input.effect_ref, (core::ChannelRef{"effect", "gpio27"}));
  EXPECT_EQ(l[0].match.pairs.size(), 10u);
  EXPECT_DOUBLE_EQ(l[0].summary.median_ms, 750.0);

  // Files named after the boards, a scenario given by name.
  std::filesystem::copy_file(file("cause.log"), file("operator.log"));
  std::filesystem::copy_file(file("effect.log"), file("vehicle.log"));
  logs.cause_file = file("operator.log");
  logs.effect_file = file("vehicle.log");
  logs.scenarios = {"track-1"};
  const auto named = analysis::analyse_inputs(logs, {});
  ASSERT_EQ(named.size(), 1u);
  EXPECT_EQ(named[0].input.scenario, "track-1");
  EXPECT_EQ(named[0].input.cause_ref, (core::ChannelRef{"operator", "gpio17"}));
  EXPECT_EQ(named[0].input.effect_ref, (core::ChannelRef{"vehicle", "gpio27"}));
}

TEST_F(PipelineTest, BadInputsFailWithTheirKind) {
  EXPECT_EQ(kind_of({}), core::ErrorKind::usage);  // nothing to read
  analysis::PipelineInputs half;
  half.cause_file = file("cause.log");
  EXPECT_EQ(kind_of(half), core::ErrorKind::usage);  // a cause file without its effect file
  analysis::PipelineInputs missing;
  missing.inputs = {file("nope.db")};
  EXPECT_EQ(kind_of(missing), core::ErrorKind::no_input);
}

}  // namespace m2mlat::analysis::pipeline_test
