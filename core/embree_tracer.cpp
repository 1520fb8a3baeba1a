// embree_tracer.cpp — BVH build and the three batched query styles.
#include "core/embree_tracer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <vector>

#include "core/error.h"
#include "core/sanitizers.h"

namespace pmc {
namespace {

static_assert(sizeof(PmcRay) == sizeof(RTCRay), "PmcRay must match RTCRay");
static_assert(offsetof(PmcRay, tfar) == offsetof(RTCRay, tfar), "PmcRay.tfar");
static_assert(offsetof(PmcRay, id) == offsetof(RTCRay, id), "PmcRay.id");
static_assert(offsetof(PmcRay, dir_x) == offsetof(RTCRay, dir_x), "PmcRay.dir_x");

constexpr size_t kGrain = 256;  // rays per task

// Runs `fn` over [0, count) in batches of about kGrain rays on TBB's workers.
// In a ThreadSanitizer build the batches run one after another on the
// calling thread instead: parallel_for's task hand-offs synchronise inside
// libtbb, which is not instrumented, so TSan reports every task as racing
// with its spawner (scripts/sanitize). The concurrency TSan checks there is
// that of application threads calling one tracer at once.
template <typename Fn>
void for_each_batch(size_t count, const Fn& fn) {
#ifdef PMC_UNDER_TSAN
  for (size_t b = 0; b < count; b += kGrain) fn(tbb::blocked_range<size_t>(b, std::min(count, b + kGrain)));
#else
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kGrain), fn);
#endif
}

void embree_error(void*, RTCError code, const char* message) {
  // Called from Embree threads: report, the failing call's result is checked by the caller.
  warn(std::string("Embree error ") + std::to_string(int(code)) + ": " + (message ? message : ""));
}

void load_ray(const PmcRay& r, RTCRayHit& rh) {
  std::memcpy(&rh.ray, &r, sizeof(RTCRay));
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

}  // namespace

// Scene triangle of a (geometry, local primitive) hit, or -1.
inline int scene_prim(const std::vector<uint32_t>* prims, unsigned geom, unsigned local) {
  return geom == RTC_INVALID_GEOMETRY_ID ? -1 : int(prims[geom][local]);
}

TraceMode parse_trace_mode(const std::string& name) {
  if (name == "stream") return TraceMode::Stream;
  if (name == "packet16") return TraceMode::Packet16;
  if (name == "single") return TraceMode::Single;
  fail_config(setting("trace_mode"), ": unknown mode '", name, "' (expected stream, packet16 or single)");
}

const char* trace_mode_name(TraceMode mode) {
  switch (mode) {
    case TraceMode::Stream:
      return "stream";
    case TraceMode::Packet16:
      return "packet16";
    default:
      return "single";
  }
}

// Embree filter callbacks: reject transparent candidate hits.
struct EmbreeFilter {
  static void run(const RTCFilterFunctionNArguments* args) {
    const EmbreeTracer* tracer = static_cast<const EmbreeTracer*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
      if (args->valid[i] != -1) continue;
      unsigned local = RTCHitN_primID(args->hit, args->N, i);
      float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
      if (tracer->alpha_->transparent(tracer->geometry_prims_[1][local], u, v)) args->valid[i] = 0;
    }
  }
};

EmbreeTracer::EmbreeTracer(const Scene& scene, TraceMode mode, const AlphaTester* alpha)
    : mode_(mode), alpha_(alpha) {
  device_ = rtcNewDevice(nullptr);
  if (!device_) fail("Embree: cannot create a device (error ", int(rtcGetDeviceError(nullptr)), ")");
  rtcSetDeviceErrorFunction(device_, embree_error, nullptr);
  scene_ = rtcNewScene(device_);
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  const std::vector<char>* cutout = alpha ? &alpha->cutout_triangles() : nullptr;
  for (uint32_t i = 0; i < scene.triangles.size(); ++i)
    geometry_prims_[cutout && (*cutout)[i] ? 1 : 0].push_back(i);
  size_t nv = scene.positions.size() / 3;
  for (unsigned g = 0; g < 2; ++g) {
    const std::vector<uint32_t>& prims = geometry_prims_[g];
    if (prims.empty()) continue;
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree reads vertex buffers with 16-byte loads: pad by one float.
    float* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                            RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv + 1));
    std::memcpy(vb, scene.positions.data(), nv * 3 * sizeof(float));
    vb[3 * nv] = vb[3 * nv + 1] = vb[3 * nv + 2] = 0.0f;
    unsigned* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), prims.size()));
    for (size_t i = 0; i < prims.size(); ++i)
      for (int k = 0; k < 3; ++k) ib[3 * i + k] = unsigned(scene.triangles[prims[i]].v[k]);
    if (g == 1) {
      rtcSetGeometryUserData(geom, this);
      rtcSetGeometryIntersectFilterFunction(geom, EmbreeFilter::run);
      rtcSetGeometryOccludedFilterFunction(geom, EmbreeFilter::run);
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(scene_, geom, g);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(scene_);
  if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) fail("Embree: building the BVH failed");
}

EmbreeTracer::~EmbreeTracer() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

void EmbreeTracer::intersect(const PmcRay* rays, PmcHit* hits, size_t count, bool coherent) const {
  const TraceMode mode = mode_;
  const std::vector<uint32_t>* prims = geometry_prims_;
  auto write_hit = [](const RTCRayHit& rh, PmcHit& hit, const std::vector<uint32_t>* p) {
    bool found = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    hit.t = found ? rh.ray.tfar : INFINITY;
    hit.u = rh.hit.u;
    hit.v = rh.hit.v;
    hit.prim = found ? scene_prim(p, rh.hit.geomID, rh.hit.primID) : -1;
  };
  RTCScene scene = scene_;
  for_each_batch(count, [&](const tbb::blocked_range<size_t>& r) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    if (mode == TraceMode::Single) {
      for (size_t i = r.begin(); i < r.end(); ++i) {
        RTCRayHit rh;
        load_ray(rays[i], rh);
        rtcIntersect1(scene, &ctx, &rh);
        write_hit(rh, hits[i], prims);
      }
    } else if (mode == TraceMode::Stream) {
      // TBB's auto partitioner may hand out ranges larger than the grain: batch them.
      RTCRayHit batch[kGrain];
      for (size_t b0 = r.begin(); b0 < r.end(); b0 += kGrain) {
        size_t n = std::min(kGrain, r.end() - b0);
        for (size_t i = 0; i < n; ++i) load_ray(rays[b0 + i], batch[i]);
        rtcIntersect1M(scene, &ctx, batch, unsigned(n), sizeof(RTCRayHit));
        for (size_t i = 0; i < n; ++i) write_hit(batch[i], hits[b0 + i], prims);
      }
    } else {
      for (size_t base = r.begin(); base < r.end(); base += 16) {
        RTCRayHit16 p;
        // Embree reads the packet and its valid mask with aligned 512-bit
        // loads: both must be 64-byte aligned (RTCRayHit16 is; a plain int
        // array is not, and crashed under AddressSanitizer's stack layout).
        alignas(64) int valid[16];
        for (int k = 0; k < 16; ++k) {
          size_t i = base + k;
          valid[k] = i < r.end() ? -1 : 0;
          const PmcRay& ray = rays[i < r.end() ? i : base];
          p.ray.org_x[k] = ray.org_x, p.ray.org_y[k] = ray.org_y, p.ray.org_z[k] = ray.org_z;
          p.ray.dir_x[k] = ray.dir_x, p.ray.dir_y[k] = ray.dir_y, p.ray.dir_z[k] = ray.dir_z;
          p.ray.tnear[k] = ray.tnear, p.ray.tfar[k] = ray.tfar, p.ray.time[k] = 0.0f;
          p.ray.mask[k] = ray.mask, p.ray.id[k] = ray.id, p.ray.flags[k] = 0;
          p.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
          p.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect16(valid, scene, &ctx, &p);
        for (int k = 0; k < 16 && base + k < r.end(); ++k) {
          PmcHit& h = hits[base + k];
          bool found = p.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
          h.t = found ? p.ray.tfar[k] : INFINITY;
          h.u = p.hit.u[k];
          h.v = p.hit.v[k];
          h.prim = found ? scene_prim(prims, p.hit.geomID[k], p.hit.primID[k]) : -1;
        }
      }
    }
  });
}

void EmbreeTracer::occluded(const PmcRay* rays, uint8_t* occluded, size_t count) const {
  const TraceMode mode = mode_;
  RTCScene scene = scene_;
  for_each_batch(count, [&](const tbb::blocked_range<size_t>& r) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    if (mode == TraceMode::Stream) {
      RTCRay batch[kGrain];
      for (size_t b0 = r.begin(); b0 < r.end(); b0 += kGrain) {
        size_t n = std::min(kGrain, r.end() - b0);
        std::memcpy(batch, rays + b0, n * sizeof(RTCRay));
        rtcOccluded1M(scene, &ctx, batch, unsigned(n), sizeof(RTCRay));
        for (size_t i = 0; i < n; ++i) occluded[b0 + i] = batch[i].tfar < 0.0f;
      }
    } else {
      // Packets buy little for incoherent shadow rays; single rays here.
      for (size_t i = r.begin(); i < r.end(); ++i) {
        RTCRay ray;
        std::memcpy(&ray, &rays[i], sizeof(RTCRay));
        rtcOccluded1(scene, &ctx, &ray);
        occluded[i] = ray.tfar < 0.0f;
      }
    }
  });
}

}  // namespace pmc
