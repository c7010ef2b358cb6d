// Setting fields from text: every field round-trips, errors name the field and change nothing.
#include "m2mlat/sim/overrides.hpp"

#include <gtest/gtest.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/sim/presets.hpp"

using namespace m2mlat;
using namespace m2mlat::sim;
using namespace std::chrono_literals;

TEST(Overrides, EveryFieldRoundTrips) {
  for (const PresetInfo& info : presets()) {
    const RigConfig original = preset(info.name);
    const auto fields = describe(original);
    ASSERT_GT(fields.size(), 80u);
    RigConfig rebuilt;
    rebuilt.network = network_profile("wired");  // different from every preset's, to be overwritten
    rebuilt.sync = sync_profile("free");
    for (const auto& [key, value] : fields) set_field(rebuilt, key, value);
    rebuilt.network.name = original.network.name;  // a field-by-field copy renames it "custom"
    EXPECT_EQ(rebuilt, original) << info.name;
  }
}

TEST(Overrides, SetsTypedValues) {
  RigConfig config;
  const std::vector<std::string> assignments{
      "seed=42",
      "magnets_deg=0,20,40",
      "motion.interval_min=2s",
      "vehicle.actuator_lag_static.offset=700ms",
      "vehicle.actuator_lag_static.shape=lognormal",
      "vehicle.actuator_lag_static.log_sigma=0.1",
      "sensor.bounce_probability=0.2",
      "sensor.both_edges=true",
      "effect_sensor.dwell.offset=20ms",
      "network=5g",
      "network.loss_probability=0.05",
      "sync=autonomous",
      "effect_clock.drift_ppm=-12.5",
      "start=2026-07-04T12:30:00.25Z",
      "duration=10min",
  };
  apply_overrides(config, assignments);
  EXPECT_EQ(config.seed, 42u);
  EXPECT_EQ(config.magnets_deg, (std::vector<double>{0, 20, 40}));
  EXPECT_EQ(config.motion.interval_min, 2s);
  EXPECT_EQ(config.vehicle.actuator_lag_static.offset, 700ms);
  EXPECT_EQ(config.vehicle.actuator_lag_static.shape, Shape::lognormal);
  EXPECT_EQ(config.cause_sensor.bounce_probability, 0.2);
  EXPECT_EQ(config.effect_sensor.bounce_probability, 0.2);
  EXPECT_TRUE(config.cause_sensor.both_edges && config.effect_sensor.both_edges);
  EXPECT_EQ(get_field(config, "cause_sensor.both_edges"), "true");
  EXPECT_EQ(config.effect_sensor.dwell.offset, 20ms);
  EXPECT_EQ(config.network.loss_probability, 0.05);
  EXPECT_EQ(config.network.delay, network_profile("5g").delay);
  EXPECT_EQ(config.network.name, "custom");
  EXPECT_EQ(config.sync.mode, SyncMode::autonomous);
  EXPECT_EQ(config.effect_clock.drift_ppm, -12.5);
  EXPECT_EQ(get_field(config, "start"), "2026-07-04T12:30:00.25Z");
  EXPECT_EQ(get_field(config, "duration"), "10min");
  EXPECT_EQ(get_field(config, "motion.interval_min"), "2s");
}

TEST(Overrides, ErrorsNameTheFieldAndChangeNothing) {
  RigConfig config;
  const RigConfig before = config;
  auto message_of = [&](std::vector<std::string> assignments) {
    try {
      apply_overrides(config, assignments);
    } catch (const core::Error& e) {
      EXPECT_EQ(e.kind(), core::ErrorKind::usage);
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message_of({"seed=7", "motion.interval_min=fast"}).find("motion.interval_min"),
            std::string::npos);
  EXPECT_NE(message_of({"seed=7", "no.such.key=1"}).find("no.such.key"), std::string::npos);
  EXPECT_NE(message_of({"seed=-1"}).find("seed"), std::string::npos);
  EXPECT_NE(message_of({"network=carrier_pigeon"}).find("network"), std::string::npos);
  EXPECT_NE(message_of({"seed"}).find("key=value"), std::string::npos);
  EXPECT_NE(message_of({"magnets_deg=0,x"}).find("magnets_deg"), std::string::npos);
  EXPECT_NE(message_of({"sensor.both_edges=yes"}).find("true or false"), std::string::npos);
  // A pass released before its bounces are over: refused, naming the field.
  EXPECT_NE(
      message_of({"sensor.dwell.min=2ms", "sensor.dwell.offset=2ms", "sensor.dwell.scale=0"}).find("dwell"),
      std::string::npos);
  // Each value parses, but the result is invalid: rejected as a whole.
  EXPECT_NE(message_of({"seed=7", "motion.interval_min=9s"}).find("motion.interval_min"), std::string::npos);
  EXPECT_EQ(config, before);
  EXPECT_THROW(set_field(config, "cause_sensor.miss_probability", "1e"), core::Error);
  EXPECT_EQ(config, before);
}

TEST(Overrides, FieldListHasHelp) {
  for (const FieldInfo& field : settable_fields()) {
    EXPECT_FALSE(field.key.empty());
    EXPECT_FALSE(field.help.empty()) << field.key;
  }
}

TEST(Overrides, UtcTimes) {
  EXPECT_EQ(parse_utc("2026-06-01T09:00:00Z"), 1'780'304'400'000'000'000);
  EXPECT_EQ(parse_utc("1970-01-01T00:00:00.000000001Z"), 1);
  EXPECT_EQ(parse_utc("1780304400.5"), 1'780'304'400'500'000'000);
  EXPECT_EQ(parse_utc("2024-02-29T23:59:59Z"), 1'709'251'199'000'000'000);
  EXPECT_THROW(parse_utc("2025-02-29T00:00:00Z"), core::Error);  // not a leap year
  EXPECT_THROW(parse_utc("2026-06-01 09:00"), core::Error);
  EXPECT_THROW(parse_utc("2026-06-01T09:00:00.1234567891Z"), core::Error);
  EXPECT_EQ(format_utc(1'780'304'400'000'000'000), "2026-06-01T09:00:00Z");
  EXPECT_EQ(format_utc(-1), "1969-12-31T23:59:59.999999999Z");
  for (std::int64_t ns : {0LL, 951'782'400'123'000'000LL, 4'102'444'800'000'000'001LL})
    EXPECT_EQ(parse_utc(format_utc(ns)), ns);
}
