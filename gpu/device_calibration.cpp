// device_calibration.cpp — measuring, storing and reading a device's cache
// costs (device_calibration.h).
#include "gpu/device_calibration.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "core/content_hash.h"
#include "core/error.h"
#include "gpu/program.h"

namespace pmc {
namespace {

constexpr const char* kKernelFile = "device_calibration.cl";
constexpr int kFormat = 1;

// The calibration kernels' own figures on the device the table was measured
// on (PoCL, pthread-skylake-avx512, 2 shared cores; docs/BENCHMARKS.md "Cache
// cost model"): a hit's lookup and a miss with its insert in 2D Perlin
// noises (medians of five calibrations: 1.08-2.11 and 1.33-2.61), and the
// noise's time, which other load on the machine inflates far more than a
// render's (16.4 ns at load 3.4, 80 at 6, 411 at 9): the least loaded one,
// so that an idle machine's unit node comes out near the table's 1.55 ns.
// Decisions use the ratios only; the unit's time scales predicted seconds.
constexpr double kReferenceLookupPerUnit = 1.5;
constexpr double kReferenceMissPerUnit = 2.2;
constexpr double kReferenceUnitNs = 16.4;

bool positive_finite(const nlohmann::json& j, const char* name, double& out) {
  auto it = j.find(name);
  if (it == j.end() || !it->is_number()) return false;
  out = it->get<double>();
  return std::isfinite(out) && out > 0.0;
}

nlohmann::json to_json(const std::string& key, const DeviceTimings& t) {
  nlohmann::json j;
  j["format"] = kFormat;
  j["key"] = key;
  j["unit_ns"] = t.unit_ns;
  j["lookup_ns"] = t.lookup_ns;
  j["miss_ns"] = t.miss_ns;
  if (t.table) j["table"] = true;  // not measured: the machine was too busy
  return j;
}

// Seconds of one launch of `k` over `items` work-items.
double launch_seconds(const ClContext& cl, cl_kernel k, size_t items) {
  cl_check(clFinish(cl.queue()), "clFinish");
  const auto t0 = std::chrono::steady_clock::now();
  enqueue_1d(cl.queue(), k, items);
  cl_check(clFinish(cl.queue()), "clFinish");
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

std::string calibration_key(const ClContext& cl) {
  const ClDeviceInfo& d = cl.info();
  ContentHash source;
  source.str(kernel_code_of(expand_kernel_source(kKernelFile)));  // comments and layout do not count
  return d.platform + " | " + d.name + " | " + d.version + " | driver " +
         cl_device_string(d.device_id, CL_DRIVER_VERSION) + " | calibration " + std::to_string(kFormat) +
         " " + source.hex();
}

std::string calibration_folder() {
  if (const char* env = std::getenv("PMC_CACHE_COSTS"); env && *env)
    return std::string(env) == "table" ? "" : env;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return std::string(xdg) + "/pmc/device-costs";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::string(home) + "/.cache/pmc/device-costs";
  return "";
}

std::string calibration_path(const std::string& folder, const std::string& key) {
  ContentHash h;
  h.str(key);
  return folder + "/" + h.hex() + ".json";
}

std::optional<DeviceTimings> read_calibration(const std::string& path, const std::string& key,
                                              std::string* problem) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;  // not measured yet: no problem
  auto bad = [&](const std::string& why) -> std::optional<DeviceTimings> {
    if (problem) *problem = path + ": " + why;
    return std::nullopt;
  };
  std::ostringstream text;
  text << in.rdbuf();
  nlohmann::json j = nlohmann::json::parse(text.str(), nullptr, false);
  if (j.is_discarded() || !j.is_object()) return bad("not a JSON object (a damaged calibration file)");
  if (!j.contains("format") || j["format"] != kFormat)
    return bad("not a calibration of format " + std::to_string(kFormat));
  if (!j.contains("key") || !j["key"].is_string() || j["key"].get<std::string>() != key)
    return bad("calibrates another device or pmc ('" + (j.contains("key") ? j["key"].dump() : "") + "')");
  DeviceTimings t;
  if (!positive_finite(j, "unit_ns", t.unit_ns) || !positive_finite(j, "lookup_ns", t.lookup_ns) ||
      !positive_finite(j, "miss_ns", t.miss_ns))
    return bad("unit_ns, lookup_ns and miss_ns must be positive numbers");
  auto table = j.find("table");
  t.table = table != j.end() && table->is_boolean() && table->get<bool>();
  return t;
}

DeviceTimings store_calibration(const std::string& folder, const std::string& key, const DeviceTimings& t) {
  namespace fs = std::filesystem;
  const std::string path = calibration_path(folder, key);
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  std::error_code ec;
  fs::create_directories(folder, ec);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << to_json(key, t).dump(2) << "\n";
    if (!out.flush()) {
      std::remove(tmp.c_str());
      warn("device calibration: cannot write " + folder + " (the measured costs are used for this run only)");
      return t;
    }
  }
  // link() fails if the file exists: the first writer's figures stay.
  if (::link(tmp.c_str(), path.c_str()) != 0) {
    std::string problem;
    if (std::optional<DeviceTimings> stored = read_calibration(path, key, &problem)) {
      std::remove(tmp.c_str());
      return *stored;
    }
    fs::rename(tmp, path, ec);  // a damaged file (already warned about): replace it
    if (ec) std::remove(tmp.c_str());
    return t;
  }
  std::remove(tmp.c_str());
  return t;
}

CpuTimes cpu_times() {
  CpuTimes t;
  rusage own{};
  if (getrusage(RUSAGE_SELF, &own) == 0)
    t.self = double(own.ru_utime.tv_sec) + 1e-6 * double(own.ru_utime.tv_usec) + double(own.ru_stime.tv_sec) +
             1e-6 * double(own.ru_stime.tv_usec);
  std::ifstream stat("/proc/stat");
  std::string cpu;
  // cpu  user nice system idle iowait irq softirq steal (guest time is inside user)
  double user = 0, nice = 0, system = 0, idle = 0, iowait = 0, irq = 0, softirq = 0, steal = 0;
  const long hz = sysconf(_SC_CLK_TCK);
  if (stat >> cpu >> user >> nice >> system >> idle >> iowait >> irq >> softirq && cpu == "cpu" && hz > 0) {
    if (!(stat >> steal)) steal = 0;
    t.machine_busy = (user + nice + system + irq + softirq + steal) / double(hz);
    t.machine_total = t.machine_busy + (idle + iowait) / double(hz);
  }
  return t;
}

double others_share(const CpuTimes& a, const CpuTimes& b) {
  if (a.machine_total < 0 || b.machine_total < 0) return 0;
  const double total = b.machine_total - a.machine_total;
  const long hz = sysconf(_SC_CLK_TCK);
  if (!(total * double(hz > 0 ? hz : 100) >= 20.0)) return 0;  // under 20 ticks: too coarse to tell
  const double others = (b.machine_busy - a.machine_busy) - (b.self - a.self);
  return std::clamp(others / total, 0.0, 1.0);
}

DeviceTimings table_timings() {
  DeviceTimings t;
  t.unit_ns = kReferenceUnitNs;
  t.lookup_ns = kReferenceLookupPerUnit * kReferenceUnitNs;
  t.miss_ns = kReferenceMissPerUnit * kReferenceUnitNs;
  t.table = true;
  return t;
}

DeviceTimings load_or_measure(const std::string& folder, const std::string& key,
                              const std::function<DeviceTimings()>& measure, double busy_share) {
  std::string problem;
  if (std::optional<DeviceTimings> stored = read_calibration(calibration_path(folder, key), key, &problem))
    return *stored;
  if (!problem.empty()) warn("device calibration: ignoring " + problem + "; measuring the device again");
  DeviceTimings t = measure();
  if (t.others_share > busy_share) {
    char share[32];
    std::snprintf(share, sizeof share, "%.0f%%", 100.0 * t.others_share);
    warn(std::string("device calibration: other processes took ") + share +
         " of the machine's CPU time while pmc timed this device's cache costs, which slows the "
         "timing kernels unevenly; pmc keeps the built-in table's figures for this device instead (" +
         calibration_path(folder, key) + ": delete it to measure again on a quieter machine)");
    t = table_timings();
  }
  return store_calibration(folder, key, t);
}

CacheCosts calibrated_costs(const DeviceTimings& t, bool gpu, const std::string& source) {
  CacheCosts c = default_cache_costs(gpu);
  c.lookup *= (t.lookup_ns / t.unit_ns) / kReferenceLookupPerUnit;
  c.miss *= (t.miss_ns / t.unit_ns) / kReferenceMissPerUnit;
  c.unit_ns *= t.unit_ns / kReferenceUnitNs;
  c.source = source;
  return c;
}

DeviceTimings measure_device_costs(const ClContext& cl) {
  const bool gpu = cl.info().is_gpu;
  ClProgram program(cl, kKernelFile,
                    std::string("-DPMC_CELL_CHUNK=") + (gpu ? "8" : "1 -DPMC_CELL_VECTOR=1"));
  // A table the size of the default scene's (131072 cells x 8 entries, 8 MiB)
  // filled to a quarter, as a frame's keys fill theirs at load factor 1/2.
  const uint64_t cells = 131072;
  const uint32_t ways = 8;
  const size_t items = gpu ? 262144 : 65536;
  const uint32_t iterations = gpu ? 1 : 4;
  ClBuffer table = cl.buffer(cells * ways * sizeof(uint64_t));
  ClBuffer out = cl.buffer(items * sizeof(float));
  const std::vector<uint64_t> zeros(cells * ways, 0);
  auto clear = [&] {
    cl_check(clEnqueueWriteBuffer(cl.queue(), table.get(), CL_TRUE, 0, zeros.size() * sizeof(uint64_t),
                                  zeros.data(), 0, nullptr, nullptr),
             "clEnqueueWriteBuffer");
  };
  const double ops = double(items) * double(iterations);
  const uint32_t unit_iterations = iterations * 16;
  cl_kernel miss = program.kernel("pmc_calibrate_miss");
  set_kernel_args(miss, table, cells, ways, iterations, out);
  cl_kernel lookup = program.kernel("pmc_calibrate_lookup");
  set_kernel_args(lookup, table, cells, ways, iterations, out);
  cl_kernel unit = program.kernel("pmc_calibrate_unit");
  set_kernel_args(unit, unit_iterations, out);
  // Rounds of all three, the fastest of each: the ratios matter, and other
  // work on the machine slows a kernel, never speeds it up. The first round
  // is a warm-up (some drivers compile at the first launch).
  double miss_s = 1e300, lookup_s = 1e300, unit_s = 1e300;
  const CpuTimes before = cpu_times();
  for (int round = 0; round < 8; ++round) {
    clear();
    const double m = launch_seconds(cl, miss, items);
    const double l = launch_seconds(cl, lookup, items);
    const double u = launch_seconds(cl, unit, items);
    if (round == 0) continue;
    miss_s = std::min(miss_s, m);
    lookup_s = std::min(lookup_s, l);
    unit_s = std::min(unit_s, u);
  }
  DeviceTimings t;
  // Another process's load only matters to a CPU device, whose cores it shares.
  t.others_share = gpu ? 0.0 : others_share(before, cpu_times());
  t.miss_ns = 1e9 * miss_s / ops;
  t.lookup_ns = 1e9 * lookup_s / ops;
  t.unit_ns = 1e9 * unit_s / (double(items) * double(unit_iterations));
  return t;
}

CacheCosts device_cache_costs(const ClContext& cl, double busy_share) {
  const bool gpu = cl.info().is_gpu;
  const std::string folder = calibration_folder();
  if (folder.empty()) return default_cache_costs(gpu);
  const std::string key = calibration_key(cl);
  const DeviceTimings t = load_or_measure(
      folder, key, [&] { return measure_device_costs(cl); }, busy_share);
  const std::string path = calibration_path(folder, key);
  return calibrated_costs(
      t, gpu,
      t.table ? "table (kept in " + path + ": the machine was too busy to measure)" : "calibrated, " + path);
}

}  // namespace pmc
