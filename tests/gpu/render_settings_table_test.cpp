// render_settings_table_test.cpp — every line of gpu/render_settings_table.h
// is a flag, a checked range, a hashed (or deliberately unhashed) setting and
// a default that `pmc info --settings` reports.
//
// The tests walk the table, so a setting added to it is checked here without
// a line of its own: its flag must be in `pmc render --help`, a value outside
// its range must be refused naming it (by its name here, by its flag through
// the binary), a change of a setting marked hashed must change the part's
// settings hash and one of a setting marked NO or PROGRAM must not.
#include "gpu/render_settings_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "gpu/part_identity.h"
#include "gpu/render_config.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

RenderConfig valid() {
  RenderConfig c;
  c.scene = "/nonexistent/scene.obj";
  return c;
}

// A valid value other than the default: a number at the far end of its range
// (one above the default when that is the lower end of an unbounded range),
// a word setting's next word.
template <typename T>
T other_value(const SettingInfo<T>& info) {
  if constexpr (kWordSetting<T>) {
    const int n = int(setting_words(info.value).size());
    return frame_value<T>((frame_value<int>(info.dflt) + 1) % n);
  } else {
    if (std::isfinite(info.hi) && T(info.hi) != info.dflt) return T(info.hi);
    if (T(info.lo) != info.dflt) return T(info.lo);
    return T(info.dflt + 1);  // unbounded above, the default at its lower end
  }
}

// The settings hash of `c` as the session resolves it: the table sized from
// cache_entries (gpu/render_session.cpp's size_cache), one cell.
std::string hash_of(const RenderConfig& c) {
  RenderSettings s = base_render_settings(c);
  s.cache.cells = 1;
  s.cache.ways = uint32_t(c.cache_entries);
  return settings_hash(s);
}

TEST(RenderSettingsTable, EverySettingHasItsFlagInRenderHelp) {
  std::string help;
  ASSERT_EQ(test::run_pmc("render --help", &help), 0) << help;
  visit_render_settings([&](const auto& info, auto, auto) {
    using T = std::decay_t<decltype(info.dflt)>;
    std::string value = info.value;
    if constexpr (kWordSetting<T>) {
      value.clear();
      for (const std::string& w : shown_setting_words(info.value)) value += (value.empty() ? "" : "|") + w;
    }
    const std::string option = std::string(info.flag) + " " + value;
    EXPECT_NE(help.find(option), std::string::npos) << option << " is not in pmc render --help:\n" << help;
  });
}

TEST(RenderSettingsTable, HashedSettingsChangeThePartHashAndOthersDoNot) {
  RenderConfig base = valid();
  base.cache_bandwidth = CacheBandwidth::On;  // max_refine and feature_texels only matter with level floors
  const std::string base_hash = hash_of(base);
  int hashed = 0;
  visit_render_settings([&](const auto& info, auto config_field, auto) {
    RenderConfig c = base;
    auto& v = config_field(c);
    v = (v == other_value(info)) ? info.dflt : other_value(info);
    ASSERT_NO_THROW(c.validate()) << info.name;
    const bool changes = hash_of(c) != base_hash;
    if (info.hash == SettingHash::Tag || info.hash == SettingHash::Fixed) {
      ++hashed;
      EXPECT_TRUE(changes) << info.name << " is marked hashed but a change leaves the settings hash alone";
    } else {
      EXPECT_FALSE(changes) << info.name << " is marked " << (info.hash == SettingHash::No ? "NO" : "PROGRAM")
                            << " but changes the settings hash";
    }
  });
  EXPECT_GE(hashed, 10);
}

TEST(RenderSettingsTable, TaggedCacheSettingsCountOnlyWithTheCacheOnAndOffTheirDefaults) {
  // A TAG setting at its default adds nothing to the hash, so a part rendered
  // before the setting existed keeps its hash.
  const RenderConfig c = valid();
  RenderConfig spread = c;
  spread.cache_lobe_spread = 0.03125f;
  EXPECT_NE(hash_of(spread), hash_of(c));
  spread.cache_lobe_spread = kDefaultCacheLobeSpread;
  EXPECT_EQ(hash_of(spread), hash_of(c));
  RenderConfig off = c, spread_off = c;
  off.cache = spread_off.cache = false;
  spread_off.cache_lobe_spread = 0.03125f;  // no cache: no cells to widen
  EXPECT_EQ(hash_of(spread_off), hash_of(off));
}

TEST(RenderSettingsTable, OutOfRangeValuesAreRefusedNamingTheSetting) {
  int checked = 0;
  visit_render_settings([&](const auto& info, auto config_field, auto) {
    using T = std::decay_t<decltype(info.dflt)>;
    if constexpr (!kWordSetting<T>) {
      if (!*info.check) return;  // checked with others (width, height)
      std::vector<T> bad;
      if (std::isfinite(info.lo)) bad.push_back(T(info.lo - 1));
      if (std::isfinite(info.hi) && info.hi + 1 <= double(std::numeric_limits<T>::max()))
        bad.push_back(T(info.hi + 1));
      if constexpr (std::is_floating_point_v<T>) bad.push_back(std::numeric_limits<T>::quiet_NaN());
      for (T b : bad) {
        RenderConfig c = valid();
        config_field(c) = b;
        try {
          c.validate();
          ADD_FAILURE() << info.name << " = " << b << " accepted";
        } catch (const ConfigError& e) {
          ASSERT_FALSE(e.settings().empty()) << e.what();
          EXPECT_EQ(e.settings()[0], info.name) << e.what();
          const std::string check = info.check, text = check.substr(0, check.find("{}"));
          EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
        }
        ++checked;
      }
    }
  });
  EXPECT_GE(checked, 10);
}

TEST(RenderSettingsTable, OutOfRangeFlagsAreRefusedByTheBinaryWithTheFlagsName) {
  const std::string dir = test::temp_dir();
  test::write_file(dir + "/s.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  visit_render_settings([&](const auto& info, auto, auto) {
    using T = std::decay_t<decltype(info.dflt)>;
    if constexpr (!kWordSetting<T>) {
      if (!*info.check || !std::isfinite(info.lo)) return;
      std::ostringstream value;
      value << info.lo - 1;
      std::string log;
      const int code = test::run_pmc("render " + dir + "/s.obj -o " + dir + "/out.exr --quiet " +
                                         std::string(info.flag) + "=" + value.str(),
                                     &log);
      EXPECT_EQ(code, 2) << log;
      const std::string check = info.check, text = check.substr(0, check.find("{}"));
      EXPECT_NE(log.find(std::string(info.flag) + ": " + text), std::string::npos) << log;
    }
  });
  EXPECT_FALSE(test::file_exists(dir + "/out.exr"));
}

TEST(RenderSettingsTable, InfoSettingsIsJsonWithADefaultConfigsValues) {
  std::string out;
  ASSERT_EQ(test::run_pmc("info --settings", &out), 0) << out;
  const nlohmann::json table = nlohmann::json::parse(out);
  ASSERT_TRUE(table.is_array());
  const RenderConfig defaults;
  size_t i = 0;
  visit_render_settings([&](const auto& info, auto config_field, auto) {
    using T = std::decay_t<decltype(info.dflt)>;
    ASSERT_LT(i, table.size());
    const nlohmann::json& e = table[i++];
    EXPECT_EQ(e.at("name"), info.name);
    EXPECT_EQ(e.at("flag"), info.flag);
    EXPECT_EQ(e.at("help"), info.help);
    EXPECT_EQ(e.at("hashed").get<bool>(), info.hash == SettingHash::Tag || info.hash == SettingHash::Fixed);
    const T& d = config_field(defaults);
    if constexpr (kWordSetting<T>)
      EXPECT_EQ(e.at("default"), setting_words(info.value).at(size_t(frame_value<int>(d)))) << info.name;
    else
      EXPECT_EQ(e.at("default").get<T>(), d) << info.name;
  });
  EXPECT_EQ(i, table.size());
}

}  // namespace
}  // namespace pmc
