// The real device backend on a machine without GPIO: chip discovery in a made-up /dev, and errors
// from files that are not GPIO chips.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <system_error>

#include "m2mlat/capture/chip_lookup.hpp"
#include "m2mlat/capture/gpio_device.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {
namespace {

TEST(LinuxGpio, FindsChipDevicesInNumericOrder) {
  const auto dev = std::filesystem::temp_directory_path() / ("m2mlat-dev-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dev);
  for (const char* name : {"gpiochip10", "gpiochip2", "gpiochip0", "gpiochipX", "gpiomem", "tty0"})
    std::ofstream(dev / name) << "";
  const auto devices = linux_gpio_devices(dev.string());
  const auto paths = devices->chip_paths();
  ASSERT_EQ(paths.size(), 3u);
  EXPECT_EQ(paths[0], (dev / "gpiochip0").string());
  EXPECT_EQ(paths[1], (dev / "gpiochip2").string());
  EXPECT_EQ(paths[2], (dev / "gpiochip10").string());
  // A regular file is no chip: the chip-info ioctl fails with errno, which becomes a core::Error.
  EXPECT_THROW(devices->chip_info(paths[0]), std::system_error);
  EXPECT_THROW(find_chip(*devices, paths[0]), core::Error);
  std::filesystem::remove_all(dev);
}

TEST(LinuxGpio, AMissingChipIsNoInput) {
  const auto devices = linux_gpio_devices("/nonexistent-dev");
  EXPECT_TRUE(devices->chip_paths().empty());
  try {
    find_chip(*devices, "/nonexistent-dev/gpiochip0");
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::no_input);
    EXPECT_NE(std::string(e.what()).find("no such GPIO chip"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace m2mlat::capture
