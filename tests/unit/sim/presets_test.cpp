// The named scenarios resemble the reference field study: medians, spreads, and the effects the
// study reported (standing vehicle slower than driving; 5G steadier than WiFi).
#include "m2mlat/sim/presets.hpp"

#include <gtest/gtest.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/sim/simulate.hpp"
#include "sim_test_util.hpp"

using namespace m2mlat;
using namespace m2mlat::sim;

namespace {
Simulation run_preset(std::string_view name, std::int64_t manoeuvres = 4000) {
  RigConfig config = preset(name);
  config.manoeuvres = manoeuvres;
  return simulate(config);
}

struct Band {
  std::string_view preset;
  double median_lo, median_hi;  // ms
  double iqr_lo, iqr_hi;        // ms
};
}  // namespace

TEST(Presets, ListedWithDescriptionsAndValid) {
  ASSERT_EQ(presets().size(), 5u);  // the study's four and stalls
  for (const PresetInfo& info : presets()) {
    EXPECT_FALSE(info.description.empty());
    const RigConfig config = preset(info.name);
    EXPECT_EQ(config.scenario, info.name);
    EXPECT_NO_THROW(validate(config));
  }
  EXPECT_EQ(preset("static_wifi"), RigConfig{});  // the default is static_wifi
  EXPECT_THROW(preset("static_lte"), core::Error);
  EXPECT_EQ(preset("static_5g").network.name, "5g");
  EXPECT_EQ(preset("dynamic_autonomous").sync.mode, SyncMode::autonomous);
  EXPECT_EQ(preset("dynamic_co_referenced").sync.mode, SyncMode::co_referenced);
  EXPECT_GT(preset("stalls").network.stall_per_minute, 0);
}

// The study: static WiFi 874 (IQR 198), static 5G 931 (105), dynamic co-referenced 768 (142),
// dynamic autonomous 815 (146). The bands allow for the model's simplicity, not for sampling noise
// (4000 manoeuvres pin a median to a few ms).
TEST(Presets, MediansAndSpreadsResembleTheStudy) {
  const Band bands[] = {
      {"static_wifi", 830, 930, 160, 230},
      {"static_5g", 890, 970, 85, 130},
      {"dynamic_co_referenced", 740, 850, 115, 170},
      {"dynamic_autonomous", 760, 870, 115, 170},
  };
  for (const Band& band : bands) {
    const auto latencies = test::true_latencies_ms(run_preset(band.preset));
    const double median = test::quantile(latencies, 0.5);
    const double spread = test::iqr(latencies);
    EXPECT_GE(median, band.median_lo) << band.preset;
    EXPECT_LE(median, band.median_hi) << band.preset;
    EXPECT_GE(spread, band.iqr_lo) << band.preset;
    EXPECT_LE(spread, band.iqr_hi) << band.preset;
    // "Dominated by the actuator": it is most of every latency.
    EXPECT_GE(median, 750) << band.preset;
    EXPECT_LE(median, 950) << band.preset;
  }
}

TEST(Presets, StandingActuatorIsSlowerThanDriving) {
  const Simulation standing = run_preset("static_5g", 1000);
  const Simulation driving = run_preset("dynamic_co_referenced", 1000);
  std::vector<double> lag_standing, lag_driving;
  for (const auto& m : standing.manoeuvres) {
    EXPECT_FALSE(m.vehicle_moving);
    lag_standing.push_back(static_cast<double>(m.actuator_lag.count()));
  }
  for (const auto& m : driving.manoeuvres) {
    EXPECT_TRUE(m.vehicle_moving);
    lag_driving.push_back(static_cast<double>(m.actuator_lag.count()));
  }
  EXPECT_GT(test::quantile(lag_standing, 0.5), test::quantile(lag_driving, 0.5) + 80e6);
  // The actuator is the largest part of the delay.
  for (const auto& m : standing.manoeuvres) EXPECT_GT(m.actuator_lag * 2, m.total_delay());
  EXPECT_GT(test::quantile(test::true_latencies_ms(standing), 0.5),
            test::quantile(test::true_latencies_ms(driving), 0.5) + 80);
}

TEST(Presets, FiveGIsSteadierThanWifi) {
  const auto wifi = test::true_latencies_ms(run_preset("static_wifi", 3000));
  const auto five_g = test::true_latencies_ms(run_preset("static_5g", 3000));
  EXPECT_LT(test::iqr(five_g) * 1.4, test::iqr(wifi));
  // ... though slower in the middle, as in the study.
  EXPECT_GT(test::quantile(five_g, 0.5), test::quantile(wifi, 0.5));
}

TEST(Presets, LostPacketsCostACommandPeriod) {
  RigConfig config = preset("static_5g");
  config.manoeuvres = 3000;
  config.network.loss_probability = 0.3;
  const Simulation run = simulate(config);
  double lost = 0;
  for (const auto& m : run.manoeuvres) {
    lost += m.lost_packets;
    EXPECT_GE(m.network_delay, m.lost_packets * config.station.command_period + config.network.delay.offset);
  }
  // Geometric: mean p / (1 - p) = 0.43 lost packets per manoeuvre.
  EXPECT_NEAR(lost / static_cast<double>(run.manoeuvres.size()), 0.3 / 0.7, 0.05);
}
