// device_calibration.h — a device's material-cache costs, measured once and kept.
//
// The cost model (materials/node_costs.h) weighs a cache point's sub-graph
// against a lookup and a miss in unit nodes. Its table was measured inside
// renders on PoCL's CPU device; another device's lookups, inserts and nodes
// cost other amounts. measure_device_costs() times three tiny kernels
// (gpu/kernels/device_calibration.cl: lookups that hit, misses that insert,
// 2D Perlin noises as the unit node) and calibrated_costs() scales the
// table's lookup and miss by how this device's ratios to the unit node differ
// from PoCL's on the machine the table came from.
//
// Timings are noisy, so a device is measured once: the raw figures are stored
// in a JSON file named by a hash of the calibration key (platform, device,
// OpenCL and driver versions, and the calibration kernel's code, which
// changes with pmc's cache code) beside PoCL's kernel cache:
// $PMC_CACHE_COSTS if it names a folder, else $XDG_CACHE_HOME/pmc/device-costs,
// else ~/.cache/pmc/device-costs. Later runs read the file, so the plan, and
// the image, is the same on a device for every run once stored. The first
// writer wins (a file is linked into place, never replaced while valid), so
// concurrent first runs (farm parts) all use the same figures. A file with
// another key (a hash collision) or one that cannot be read as calibration is
// ignored with a warning and measured again. A measurement taken while other
// processes kept the machine busy (kCalibrationBusyShare) is not stored: the
// table's own figures are, marked as such, so that every run on the device,
// farm chunks running at once included, still plans alike.
// PMC_CACHE_COSTS=table uses the
// table without a device measurement (the test suite sets it: deterministic
// plans on any machine).
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "gpu/cl_context.h"
#include "materials/node_costs.h"

namespace pmc {

// Raw timings of the calibration kernels, nanoseconds per operation and
// device (throughput of the whole device, as node costs are measured).
struct DeviceTimings {
  double unit_ns = 0;    // one 2D Perlin noise
  double lookup_ns = 0;  // a lookup that hits
  double miss_ns = 0;    // a lookup that misses, then its insert
  // Not stored: the share of the machine's CPU time that other processes
  // took while the kernels were timed (0 when unknown; see cpu_times()).
  double others_share = 0;
  // Stored: the table's figures (table_timings()), kept because the machine
  // was too busy to measure; deleting the file measures again.
  bool table = false;
};

// The figures of the machine the table was measured on: calibrated_costs()
// of them is the table itself.
DeviceTimings table_timings();

// A calibration measured while other processes kept more than this share of
// the machine busy is not kept: their load slows the three kernels unevenly
// (one measured beside a compile on 2 cores read its lookup 4x and its unit
// node 2.4x the quiet figures), and a stored calibration plans every later
// run. The table's figures are stored in its place.
constexpr double kCalibrationBusyShare = 0.25;

// CPU seconds the machine spent busy (user, nice, system, interrupts and, in
// a virtual machine, time stolen by the host) and in all (busy and idle)
// since boot, from /proc/stat, and this process's own (getrusage); the
// machine's figures are negative where /proc/stat cannot be read.
struct CpuTimes {
  double machine_busy = -1, machine_total = -1, self = 0;
};
CpuTimes cpu_times();
// The share of the machine's CPU time between `a` and `b` that other
// processes took: (machine busy - own) / machine total, in [0, 1]; 0 when
// unknown or when the window holds too few clock ticks to tell.
double others_share(const CpuTimes& a, const CpuTimes& b);

// What identifies a device's calibration (one line of text): the platform,
// device, OpenCL and driver versions and a hash of the calibration kernel's
// code (kernel_code_of: an edit of its comments keeps the figures).
std::string calibration_key(const ClContext& cl);
// The folder from PMC_CACHE_COSTS / XDG_CACHE_HOME / HOME; "" with
// PMC_CACHE_COSTS=table or no home folder.
std::string calibration_folder();
// The file that holds `key`'s calibration in `folder`.
std::string calibration_path(const std::string& folder, const std::string& key);

// The stored timings for `key`, or none (with `problem` saying why when a
// file exists but is unusable: unreadable, not calibration JSON, another key).
std::optional<DeviceTimings> read_calibration(const std::string& path, const std::string& key,
                                              std::string* problem);
// Stores `t` unless a valid file for `key` is already there; returns the
// timings the file holds afterwards (the first writer's). A folder that
// cannot be written costs a warning and returns `t`.
DeviceTimings store_calibration(const std::string& folder, const std::string& key, const DeviceTimings& t);

// The stored timings, else measure() once and store them; when the
// measurement's others_share exceeds `busy_share`, table_timings() are
// stored instead (with a warning naming the file to delete). Either way the
// first writer's figures come back, so concurrent first runs agree.
DeviceTimings load_or_measure(const std::string& folder, const std::string& key,
                              const std::function<DeviceTimings()>& measure,
                              double busy_share = kCalibrationBusyShare);

// The table's figures scaled by a device's timings (see above).
CacheCosts calibrated_costs(const DeviceTimings& t, bool gpu, const std::string& source);

// Times the calibration kernels on the device (builds them: seconds on PoCL
// the first time, then PoCL's kernel cache).
DeviceTimings measure_device_costs(const ClContext& cl);

// The costs a render on `cl` plans with: the table (PMC_CACHE_COSTS=table or
// no folder), else the stored or newly measured calibration (the table's
// figures where the machine was too busy to measure).
CacheCosts device_cache_costs(const ClContext& cl, double busy_share = kCalibrationBusyShare);

}  // namespace pmc
