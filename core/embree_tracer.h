// embree_tracer.h — one Embree 3 device and scene; batched ray queries.
//
// The tracer owns the BVH over the scene's triangles and answers queue-sized
// batches: intersect() turns PmcRay records (laid out as RTCRay) into PmcHit
// records, occluded() into one byte per shadow ray. Batches are split over
// TBB threads; within a thread three query styles are available because their
// speed differs by workload (see docs/BENCHMARKS.md, scripts/bench-trace):
// Embree's ray streams (rtcIntersect1M), 16-wide packets (rtcIntersect16), and
// single rays (rtcIntersect1). Camera rays are flagged coherent. Triangles
// with cut-out materials live in a second geometry with filter functions.
#pragma once

#include <embree3/rtcore.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/abi/pmc_types.h"
#include "core/alpha_test.h"
#include "core/scene.h"

namespace pmc {

enum class TraceMode { Stream, Packet16, Single };

TraceMode parse_trace_mode(const std::string& name);
const char* trace_mode_name(TraceMode mode);

class EmbreeTracer {
 public:
  // Triangles flagged by `alpha` go into a second geometry whose hits the
  // tester may reject; `alpha` must outlive the tracer.
  explicit EmbreeTracer(const Scene& scene, TraceMode mode = TraceMode::Single,
                        const AlphaTester* alpha = nullptr);
  ~EmbreeTracer();
  EmbreeTracer(const EmbreeTracer&) = delete;
  EmbreeTracer& operator=(const EmbreeTracer&) = delete;

  void intersect(const PmcRay* rays, PmcHit* hits, size_t count, bool coherent) const;
  void occluded(const PmcRay* rays, uint8_t* occluded, size_t count) const;

  TraceMode mode() const { return mode_; }
  void set_mode(TraceMode mode) { mode_ = mode; }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  TraceMode mode_;
  const AlphaTester* alpha_ = nullptr;
  std::vector<uint32_t> geometry_prims_[2];  // per geometry: local primitive -> scene triangle

  friend struct EmbreeFilter;
};

}  // namespace pmc
