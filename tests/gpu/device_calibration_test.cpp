// device_calibration_test.cpp — a device's cache costs, measured once and kept
// (gpu/device_calibration.h):
//  (a) stored timings read back exactly, in a file named by the key;
//  (b) a stored key is not measured again, another key is (its own file), and
//      a file holding another key's figures is ignored with a warning;
//  (c) a damaged file (not JSON, missing or non-positive figures) is ignored
//      with a warning naming it, measured again and replaced, never a crash;
//  (d) the first writer wins: a second store keeps the first figures;
//  (e) the table's figures scale by the device's ratios (equal ratios: the
//      table itself);
//  (f) on this machine's device: the kernels measure positive figures, and
//      device_cache_costs() gives identical costs on the second call (read
//      back, not measured), so the plan is the same for every later run;
//  (g) a measurement while other processes took more than
//      kCalibrationBusyShare of the machine is not stored: the table's
//      figures are, marked, with a warning naming the file, and later runs
//      read them; others_share is the machine's busy time less our own.
#include "gpu/device_calibration.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <string>

#include "tests/support/test_support.h"

namespace pmc {
namespace {

DeviceTimings timings(double unit, double lookup, double miss) {
  DeviceTimings t;
  t.unit_ns = unit;
  t.lookup_ns = lookup;
  t.miss_ns = miss;
  return t;
}

TEST(DeviceCalibration, StoredTimingsRoundTrip) {
  const std::string dir = test::temp_dir();
  const DeviceTimings t = timings(80.123456789, 120.5, 175.25);
  const DeviceTimings kept = store_calibration(dir, "device A", t);
  EXPECT_EQ(kept.unit_ns, t.unit_ns);
  const std::string path = calibration_path(dir, "device A");
  ASSERT_TRUE(test::file_exists(path));
  std::string problem;
  std::optional<DeviceTimings> back = read_calibration(path, "device A", &problem);
  ASSERT_TRUE(back) << problem;
  EXPECT_EQ(back->unit_ns, t.unit_ns);  // exactly: the plan must not move
  EXPECT_EQ(back->lookup_ns, t.lookup_ns);
  EXPECT_EQ(back->miss_ns, t.miss_ns);
  EXPECT_NE(calibration_path(dir, "device B"), path);
}

TEST(DeviceCalibration, KeyedByDevice) {
  const std::string dir = test::temp_dir();
  int measured = 0;
  auto measure = [&measured] {
    ++measured;
    return timings(80, 120 + measured, 170);
  };
  EXPECT_EQ(load_or_measure(dir, "device A", measure).lookup_ns, 121);
  EXPECT_EQ(load_or_measure(dir, "device A", measure).lookup_ns, 121);
  EXPECT_EQ(measured, 1) << "a stored calibration is not measured again";
  EXPECT_EQ(load_or_measure(dir, "device B", measure).lookup_ns, 122);
  EXPECT_EQ(measured, 2) << "another device key is measured";
  // A's file where B's belongs (as a hash collision would put it): not B's.
  std::filesystem::copy_file(calibration_path(dir, "device A"), calibration_path(dir, "device C"));
  std::string problem;
  EXPECT_FALSE(read_calibration(calibration_path(dir, "device C"), "device C", &problem));
  EXPECT_NE(problem.find("another device"), std::string::npos) << problem;
  testing::internal::CaptureStderr();
  EXPECT_EQ(load_or_measure(dir, "device C", measure).lookup_ns, 123);
  const std::string warning = testing::internal::GetCapturedStderr();
  EXPECT_NE(warning.find(calibration_path(dir, "device C")), std::string::npos) << warning;
}

TEST(DeviceCalibration, DamagedFileIsIgnoredWithAWarning) {
  const std::string dir = test::temp_dir();
  const std::string path = calibration_path(dir, "device A");
  const std::string damaged[] = {
      "{\"format\": 1, \"key\": \"device A\", \"unit_ns\": 8",  // cut short
      "\x01\x02 not json",
      "[1, 2, 3]",
      "{\"format\": 1, \"key\": \"device A\", \"unit_ns\": 80, \"lookup_ns\": -1, \"miss_ns\": 170}",
      "{\"format\": 1, \"key\": \"device A\", \"unit_ns\": 80, \"lookup_ns\": \"fast\", \"miss_ns\": 170}",
      "{\"format\": 99, \"key\": \"device A\", \"unit_ns\": 80, \"lookup_ns\": 120, \"miss_ns\": 170}",
  };
  for (const std::string& text : damaged) {
    test::write_file(path, text);
    int measured = 0;
    testing::internal::CaptureStderr();
    const DeviceTimings t = load_or_measure(dir, "device A", [&measured] {
      ++measured;
      return timings(80, 120, 170);
    });
    const std::string warning = testing::internal::GetCapturedStderr();
    EXPECT_EQ(measured, 1) << text;
    EXPECT_EQ(t.lookup_ns, 120) << text;
    EXPECT_NE(warning.find(path), std::string::npos) << text << " -> " << warning;
    std::string problem;
    EXPECT_TRUE(read_calibration(path, "device A", &problem))
        << "replaced by the new measurement: " << problem;
  }
}

TEST(DeviceCalibration, ABusyMachineKeepsTheTablesFiguresNotItsMeasurement) {
  const std::string dir = test::temp_dir();
  int measured = 0;
  double share = 0.6;  // others took 60% of the machine while the kernels ran
  auto measure = [&] {
    ++measured;
    DeviceTimings t = timings(38, 34.7, 56.3);  // what a compile beside the timing gave
    t.others_share = share;
    return t;
  };
  testing::internal::CaptureStderr();
  const DeviceTimings busy = load_or_measure(dir, "device A", measure);
  const std::string warning = testing::internal::GetCapturedStderr();
  EXPECT_NE(warning.find("60%"), std::string::npos) << warning;
  EXPECT_NE(warning.find(calibration_path(dir, "device A")), std::string::npos) << "names the file to delete";
  EXPECT_TRUE(busy.table);
  const CacheCosts table = default_cache_costs(false), planned = calibrated_costs(busy, false, "test");
  EXPECT_NEAR(planned.lookup, table.lookup, 1e-9) << "the table's plans, not the disturbed figures'";
  EXPECT_NEAR(planned.miss, table.miss, 1e-9);
  // Stored, so that every later run (farm chunks started at once too) plans alike.
  std::string problem;
  std::optional<DeviceTimings> stored =
      read_calibration(calibration_path(dir, "device A"), "device A", &problem);
  ASSERT_TRUE(stored) << problem;
  EXPECT_TRUE(stored->table);
  EXPECT_EQ(stored->lookup_ns, busy.lookup_ns);
  share = 0.0;
  EXPECT_TRUE(load_or_measure(dir, "device A", measure).table);
  EXPECT_EQ(measured, 1) << "the kept table is read, not measured again";
  // At the limit a measurement is kept as measured.
  const std::string other = test::temp_dir();
  share = kCalibrationBusyShare;
  const DeviceTimings quiet = load_or_measure(other, "device A", measure);
  EXPECT_FALSE(quiet.table);
  EXPECT_EQ(quiet.lookup_ns, 34.7);
  EXPECT_FALSE(read_calibration(calibration_path(other, "device A"), "device A", nullptr)->table);
}

TEST(DeviceCalibration, AKeptTablePlansAsTheTableAndSaysSo) {
  // What a busy first run leaves for this device: the later runs plan with the table.
  const std::string dir = test::temp_dir();
  store_calibration(dir, calibration_key(test::cl()), table_timings());
  const char* before = std::getenv("PMC_CACHE_COSTS");
  const std::string saved = before ? before : "";
  setenv("PMC_CACHE_COSTS", dir.c_str(), 1);
  const CacheCosts costs = device_cache_costs(test::cl());
  if (before)
    setenv("PMC_CACHE_COSTS", saved.c_str(), 1);
  else
    unsetenv("PMC_CACHE_COSTS");
  const CacheCosts table = default_cache_costs(test::cl().info().is_gpu);
  EXPECT_NEAR(costs.lookup, table.lookup, 1e-9);
  EXPECT_NEAR(costs.miss, table.miss, 1e-9);
  EXPECT_NEAR(costs.unit_ns, table.unit_ns, 1e-9);
  EXPECT_NE(costs.source.find("table (kept in " + calibration_path(dir, calibration_key(test::cl()))),
            std::string::npos)
      << costs.source;
}

TEST(DeviceCalibration, OthersShareIsTheMachinesBusyTimeLessOurOwn) {
  CpuTimes a, b;
  a.machine_busy = 100, a.machine_total = 200, a.self = 10;
  b.machine_busy = 160, b.machine_total = 300, b.self = 40;  // 60 s busy of 100, 30 of them ours
  EXPECT_DOUBLE_EQ(others_share(a, b), 0.3);
  b.self = 80;  // our own time read finer than the machine's ticks: never below 0
  EXPECT_EQ(others_share(a, b), 0.0);
  b = a;
  b.machine_busy += 0.05, b.machine_total += 0.1;  // 10 ticks at 100 Hz: too few to tell
  EXPECT_EQ(others_share(a, b), 0.0);
  CpuTimes unknown;  // no /proc/stat
  EXPECT_EQ(others_share(unknown, b), 0.0);
  // This machine: the counters run, and a spin of this thread shows in its own time.
  const CpuTimes before = cpu_times();
  const auto start = std::chrono::steady_clock::now();
  volatile double sink = 0;
  while (std::chrono::steady_clock::now() - start < std::chrono::milliseconds(200)) sink = sink + 1.0;
  const CpuTimes after = cpu_times();
  ASSERT_GE(before.machine_total, 0) << "/proc/stat unreadable";
  EXPECT_GT(after.machine_total, before.machine_total);
  EXPECT_LE(after.machine_busy, after.machine_total);
  EXPECT_GE(after.self - before.self, 0.1);
  const double share_now = others_share(before, after);
  EXPECT_TRUE(share_now >= 0.0 && share_now <= 1.0) << share_now;
}

TEST(DeviceCalibration, FirstWriterWins) {
  const std::string dir = test::temp_dir();
  store_calibration(dir, "device A", timings(80, 120, 170));
  const DeviceTimings second = store_calibration(dir, "device A", timings(90, 200, 300));
  EXPECT_EQ(second.lookup_ns, 120);
  EXPECT_EQ(read_calibration(calibration_path(dir, "device A"), "device A", nullptr)->lookup_ns, 120);
}

TEST(DeviceCalibration, TableScalesByTheDevicesRatios) {
  const CacheCosts table = default_cache_costs(false);
  // The reference machine's own figures (lookup 1.5 and miss 2.2 noises,
  // 16.4 ns a noise) give the table back.
  const CacheCosts same = calibrated_costs(timings(16.4, 24.6, 36.08), false, "test");
  EXPECT_NEAR(same.lookup, table.lookup, 1e-9);
  EXPECT_NEAR(same.miss, table.miss, 1e-9);
  EXPECT_NEAR(same.unit_ns, table.unit_ns, 1e-9);
  // Lookups twice as dear against the unit node, and a device twice as fast.
  const CacheCosts dear = calibrated_costs(timings(8.2, 24.6, 18.04), false, "test");
  EXPECT_NEAR(dear.lookup, 2.0 * table.lookup, 1e-9);
  EXPECT_NEAR(dear.miss, table.miss, 1e-9);
  EXPECT_NEAR(dear.unit_ns, table.unit_ns / 2.0, 1e-9);
  EXPECT_EQ(dear.source, "test");
}

TEST(DeviceCalibration, MeasuredOnceOnThisDevice) {
  const std::string dir = test::temp_dir();
  const char* before = std::getenv("PMC_CACHE_COSTS");
  const std::string saved = before ? before : "";
  setenv("PMC_CACHE_COSTS", dir.c_str(), 1);
  // Whatever else the machine runs (ctest -j): this checks storing, not load.
  const CacheCosts first = device_cache_costs(test::cl(), 1.0);
  const CacheCosts second = device_cache_costs(test::cl(), 1.0);
  if (before)
    setenv("PMC_CACHE_COSTS", saved.c_str(), 1);
  else
    unsetenv("PMC_CACHE_COSTS");
  std::string problem;
  std::optional<DeviceTimings> t = read_calibration(calibration_path(dir, calibration_key(test::cl())),
                                                    calibration_key(test::cl()), &problem);
  ASSERT_TRUE(t) << problem;
  for (double v : {t->unit_ns, t->lookup_ns, t->miss_ns}) EXPECT_TRUE(std::isfinite(v) && v > 0) << v;
  EXPECT_NE(first.source.find("calibrated"), std::string::npos) << first.source;
  EXPECT_EQ(first.lookup, second.lookup);
  EXPECT_EQ(first.miss, second.miss);
  EXPECT_EQ(first.unit_ns, second.unit_ns);
  EXPECT_NE(calibration_key(test::cl()).find(test::cl().info().name), std::string::npos);
}

}  // namespace
}  // namespace pmc
