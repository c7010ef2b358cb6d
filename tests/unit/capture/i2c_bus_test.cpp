// The I2C device handle's errors on real files: a device that does not exist, and a file that is
// not an I2C device (the ioctl is refused). The transfers themselves are tested in the real kernel
// (tests/vm: i2c-stub), as this machine has no I2C bus.
#include "m2mlat/capture/i2c_bus.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "m2mlat/core/error.hpp"

namespace m2mlat::capture::i2c_bus_test {
namespace {

TEST(I2cBus, AMissingDeviceIsNoInputAndSaysHowToGetOne) {
  try {
    I2cBus bus("/dev/i2c-does-not-exist", 0x68);
    FAIL() << "no error";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::no_input);
    const std::string what = e.what();
    EXPECT_NE(what.find("/dev/i2c-does-not-exist"), std::string::npos) << what;
    EXPECT_NE(what.find("i2c-dev"), std::string::npos) << what;
  }
}

TEST(I2cBus, AFileThatIsNotAnI2cDeviceIsRefusedNamingItAndTheAddress) {
  const auto path = std::filesystem::temp_directory_path() / ("m2mlat-i2c-" + std::to_string(::getpid()));
  std::ofstream(path) << "x";
  try {
    I2cBus bus(path.string(), 0x68);
    FAIL() << "no error";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::io);
    const std::string what = e.what();
    EXPECT_NE(what.find(path.string()), std::string::npos) << what;
    EXPECT_NE(what.find("address 0x68"), std::string::npos) << what;
  }
  std::filesystem::remove(path);
}

TEST(I2cBus, AnAddressOutsideTheSevenBitRangeIsAUsageError) {
  for (const std::uint8_t address : {std::uint8_t{0x00}, std::uint8_t{0x78}, std::uint8_t{0xff}}) {
    try {
      I2cBus bus("/dev/null", address);
      FAIL() << "no error for " << int{address};
    } catch (const core::Error& e) {
      EXPECT_EQ(e.kind(), core::ErrorKind::usage) << e.what();
    }
  }
}

}  // namespace
}  // namespace m2mlat::capture::i2c_bus_test

namespace m2mlat::capture::i2c_bus_test {
namespace {

TEST(I2cBus, AddressesAreReadInHexOrDecimalAndCheckedForRange) {
  EXPECT_EQ(parse_i2c_address("--address", "0x68"), 0x68);
  EXPECT_EQ(parse_i2c_address("--address", "0X69"), 0x69);
  EXPECT_EQ(parse_i2c_address("--address", "104"), 0x68);
  for (const char* bad : {"", "0x", "0x78", "2", "68h", "-1", "0x1ff"}) {
    try {
      parse_i2c_address("--address", bad);
      FAIL() << "no error for '" << bad << "'";
    } catch (const core::Error& e) {
      EXPECT_EQ(e.kind(), core::ErrorKind::usage);
      EXPECT_NE(std::string(e.what()).find("--address"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace m2mlat::capture::i2c_bus_test
