// cache_trace.cpp — the lookup trace's configuration and its file (cache_trace.h).
#include "gpu/cache_trace.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <vector>

#include "core/atomic_write.h"
#include "core/error.h"

namespace pmc {

namespace {

constexpr size_t kDefaultRecords = size_t(1) << 24;
constexpr size_t kMaxRecords = size_t(1) << 28;  // 4 GiB of device memory

size_t parse_records(const char* text) {
  char* end = nullptr;
  errno = 0;
  const unsigned long long n = std::strtoull(text, &end, 10);
  if (!*text || *end || errno || text[0] == '-' || n == 0 || n > kMaxRecords)
    fail("PMC_CACHE_TRACE_RECORDS='", text, "': expected a whole number of records from 1 to ", kMaxRecords);
  return size_t(n);
}

template <typename T>
void put(std::ofstream& out, T v) {
  out.write(reinterpret_cast<const char*>(&v), sizeof v);
}

}  // namespace

CacheTraceConfig cache_trace_config() {
  CacheTraceConfig c;
  const char* path = std::getenv("PMC_CACHE_TRACE");
  if (!path || !*path) return c;
  c.path = path;
  const char* records = std::getenv("PMC_CACHE_TRACE_RECORDS");
  c.records = records && *records ? parse_records(records) : kDefaultRecords;
  return c;
}

std::string cache_trace_program_option(const CacheTraceConfig& trace) {
  return trace.on() ? " -DPMC_CACHE_TRACE_RECORDS=" + std::to_string(trace.records) : "";
}

void write_cache_trace(const ClContext& cl, const ClBuffer* entries, size_t table_words,
                       const CacheTraceConfig& trace, const CacheTraceFrame& frame) {
  std::vector<uint64_t> region;
  uint64_t lookups = 0, kept = 0;
  if (entries) {
    cl.read(*entries, table_words * sizeof(uint64_t), sizeof(uint64_t), &lookups);
    kept = std::min<uint64_t>(lookups, trace.records);
    region.resize(size_t(2 * kept));
    if (kept)
      cl.read(*entries, (table_words + 1) * sizeof(uint64_t), region.size() * sizeof(uint64_t),
              region.data());
  }
  write_atomically(trace.path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) fail("cannot open '", tmp, "' for writing");
    out.write("PMCTRACE", 8);
    for (uint32_t v : {1u, frame.width, frame.height, frame.ways}) put(out, v);
    put(out, frame.cells);
    put(out, lookups);
    put(out, kept);
    out.write(reinterpret_cast<const char*>(region.data()),
              std::streamsize(region.size() * sizeof(uint64_t)));
    if (!out.flush()) fail("writing '", tmp, "' failed");
  });
}

}  // namespace pmc
