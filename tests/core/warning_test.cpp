// warning_test.cpp — warn() shows the settings a warning marks (setting())
// through the rename app/ installs, as ConfigError's messages are shown.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "core/error.h"

namespace pmc {
namespace {

std::string warned(const std::string& message) {
  testing::internal::CaptureStderr();
  warn(message);
  return testing::internal::GetCapturedStderr();
}

TEST(Warning, ShowsMarkedSettingsThroughTheInstalledRename) {
  std::ostringstream os;
  os << "set " << setting("texture_cache") << " to keep them";
  EXPECT_EQ(warned(os.str()), "pmc: warning: set texture_cache to keep them\n") << "plain names by default";
  set_warning_settings([](const std::string& name) { return "--" + name + "-flag"; });
  EXPECT_EQ(warned(os.str()), "pmc: warning: set --texture_cache-flag to keep them\n");
  set_warning_settings(nullptr);
  EXPECT_EQ(warned("no settings here"), "pmc: warning: no settings here\n");
}

}  // namespace
}  // namespace pmc
