// cache_trace.h — a diagnostic: every material-cache lookup of a render, in order.
//
// With PMC_CACHE_TRACE=FILE in the environment, the shade kernel appends one
// record per cache lookup to a region behind the cache table
// (core/device/pmc_interp.h, PMC_CACHE_TRACE_RECORDS), and the renderer writes
// them to FILE after the render. The records come in the order the lookups
// took their slots: wave by wave (a wave is one or several samples of the
// frame, or of the crop, or of a block of its pixels: gpu/wavefront_renderer.cpp),
// bounce by bounce, batch by batch; within one kernel launch the
// work-items race. That is the order a replacement policy sees, so a trace
// can be replayed against other policies, table sizes and orders
// (core/cache_replay.h, `pmc cache-replay`; docs/BENCHMARKS.md, "Cache
// replacement bounds"). PMC_CACHE_TRACE_RECORDS sets the capacity (default 2^24 records,
// 256 MiB of device memory); lookups past it are counted, not kept. The trace
// costs an atomic per lookup: time a render without it.
//
// File (little-endian): the 8 bytes "PMCTRACE"; u32 version (1), width,
// height, entries per cell; u64 table cells, lookups, records kept; then the
// records, two u64 each:
//   key:  the cache key's 64-bit hash h1 (its cell is h1 mod cells; keys with
//         equal h1 are taken as one)
//   info: bits 0-31 the pixel (y * width + x, frame coordinates), 32-39 the
//         depth (surface hits before this one; 0: a camera-ray hit), 40-59
//         the sample index, 60 set for a position cell.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "gpu/cl_context.h"

namespace pmc {

struct CacheTraceConfig {
  std::string path;    // empty: no trace
  size_t records = 0;  // capacity of the record region
  bool on() const { return !path.empty(); }
  // 64-bit words of the region behind the table: a count, then the records.
  size_t words() const { return on() ? 1 + 2 * records : 0; }
};

// From PMC_CACHE_TRACE and PMC_CACHE_TRACE_RECORDS; a malformed count fails
// with an error that names the variable.
CacheTraceConfig cache_trace_config();

// " -DPMC_CACHE_TRACE_RECORDS=N" while tracing, else "".
std::string cache_trace_program_option(const CacheTraceConfig& trace);

struct CacheTraceFrame {
  uint32_t width = 0, height = 0;
  uint64_t cells = 0;
  uint32_t ways = 0;
};

// Reads the region that starts at word `table_words` of `entries` and writes
// the file (atomically). `entries` is null when the cache was off: the file
// then holds no records.
void write_cache_trace(const ClContext& cl, const ClBuffer* entries, size_t table_words,
                       const CacheTraceConfig& trace, const CacheTraceFrame& frame);

}  // namespace pmc
