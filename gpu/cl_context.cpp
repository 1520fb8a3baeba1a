// cl_context.cpp — platform/device discovery and checked OpenCL wrappers.
#include "gpu/cl_context.h"

#include <algorithm>
#include <cctype>

#include "core/error.h"

namespace pmc {
namespace {

std::string platform_string(cl_platform_id p, cl_platform_info what) {
  size_t n = 0;
  if (clGetPlatformInfo(p, what, 0, nullptr, &n) != CL_SUCCESS || n == 0) return {};
  std::string s(n, '\0');
  clGetPlatformInfo(p, what, n, s.data(), nullptr);
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower((unsigned char)c));
  return s;
}

}  // namespace

void cl_check(cl_int status, const char* what) {
  if (status != CL_SUCCESS) fail("OpenCL: ", what, " failed with error ", status);
}

std::string cl_device_string(cl_device_id d, cl_device_info what) {
  size_t n = 0;
  if (clGetDeviceInfo(d, what, 0, nullptr, &n) != CL_SUCCESS || n == 0) return {};
  std::string s(n, '\0');
  clGetDeviceInfo(d, what, n, s.data(), nullptr);
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

std::vector<ClDeviceInfo> list_cl_devices() {
  cl_uint np = 0;
  cl_int st = clGetPlatformIDs(0, nullptr, &np);
  if (st != CL_SUCCESS || np == 0)
    fail("no OpenCL platform found (clGetPlatformIDs returned ", st,
         "). Install an OpenCL driver: on Debian, 'sudo apt-get install pocl-opencl-icd "
         "ocl-icd-libopencl1' gives a CPU device (or run scripts/setup)");
  std::vector<cl_platform_id> platforms(np);
  cl_check(clGetPlatformIDs(np, platforms.data(), nullptr), "clGetPlatformIDs");
  std::vector<ClDeviceInfo> out;
  for (cl_platform_id p : platforms) {
    cl_uint nd = 0;
    if (clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, 0, nullptr, &nd) != CL_SUCCESS || nd == 0) continue;
    std::vector<cl_device_id> devices(nd);
    clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, nd, devices.data(), nullptr);
    for (cl_device_id d : devices) {
      ClDeviceInfo info;
      info.platform = platform_string(p, CL_PLATFORM_NAME);
      info.name = cl_device_string(d, CL_DEVICE_NAME);
      info.version = cl_device_string(d, CL_DEVICE_VERSION);
      cl_device_type type = 0;
      clGetDeviceInfo(d, CL_DEVICE_TYPE, sizeof(type), &type, nullptr);
      info.is_gpu = (type & CL_DEVICE_TYPE_GPU) != 0;
      info.is_cpu = (type & CL_DEVICE_TYPE_CPU) != 0;
      cl_bool unified = CL_FALSE;
      clGetDeviceInfo(d, CL_DEVICE_HOST_UNIFIED_MEMORY, sizeof(unified), &unified, nullptr);
      info.host_unified_memory = unified == CL_TRUE;
      cl_ulong mem = 0;
      clGetDeviceInfo(d, CL_DEVICE_GLOBAL_MEM_SIZE, sizeof(mem), &mem, nullptr);
      info.global_memory = size_t(mem);
      cl_uint cu = 0;
      clGetDeviceInfo(d, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof(cu), &cu, nullptr);
      info.compute_units = cu;
      info.platform_id = p;
      info.device_id = d;
      out.push_back(info);
    }
  }
  if (out.empty())
    fail(
        "OpenCL platforms exist but none has a device. Install PoCL for a CPU device: "
        "'sudo apt-get install pocl-opencl-icd'");
  return out;
}

ClBuffer::ClBuffer(cl_context ctx, size_t bytes, cl_mem_flags flags, void* host) : bytes_(bytes) {
  cl_int st = CL_SUCCESS;
  // A host pointer's buffer is exactly its bytes; others get at least 16.
  mem_ = clCreateBuffer(ctx, flags, host ? bytes : std::max<size_t>(bytes, 16), host, &st);
  if (st != CL_SUCCESS)
    fail("OpenCL: cannot allocate a buffer of ", bytes, " bytes (error ", st,
         "): the device may be out of memory");
}

ClBuffer::~ClBuffer() {
  if (mem_) clReleaseMemObject(mem_);
}

ClBuffer& ClBuffer::operator=(ClBuffer&& o) noexcept {
  if (this != &o) {
    if (mem_) clReleaseMemObject(mem_);
    mem_ = std::exchange(o.mem_, nullptr);
    bytes_ = o.bytes_;
  }
  return *this;
}

ClContext::ClContext(const std::string& device_filter) {
  std::vector<ClDeviceInfo> devices = list_cl_devices();
  const ClDeviceInfo* pick = nullptr;
  if (!device_filter.empty()) {
    std::string f = lower(device_filter);
    for (const ClDeviceInfo& d : devices)
      if (lower(d.name).find(f) != std::string::npos || lower(d.platform).find(f) != std::string::npos) {
        pick = &d;
        break;
      }
    if (!pick) {
      std::string names;
      for (const ClDeviceInfo& d : devices) names += "\n  " + d.name + " (" + d.platform + ")";
      fail_config(setting("device"), ": no OpenCL device matches '", device_filter, "'; available:", names);
    }
  } else {
    for (const ClDeviceInfo& d : devices)
      if (d.is_gpu) {
        pick = &d;
        break;
      }
    if (!pick) pick = &devices.front();
  }
  info_ = *pick;
  cl_int st = CL_SUCCESS;
  context_ = clCreateContext(nullptr, 1, &info_.device_id, nullptr, nullptr, &st);
  cl_check(st, "clCreateContext");
  queue_ = ClQueue(context_, info_.device_id);
}

ClContext::~ClContext() {
  queue_ = ClQueue();  // before the context
  if (context_) clReleaseContext(context_);
}

ClQueue::ClQueue(cl_context ctx, cl_device_id device) {
  cl_int st = CL_SUCCESS;
  queue_ = clCreateCommandQueue(ctx, device, CL_QUEUE_PROFILING_ENABLE, &st);
  cl_check(st, "clCreateCommandQueue");
}

ClQueue::~ClQueue() {
  if (queue_) clReleaseCommandQueue(queue_);
}

ClQueue& ClQueue::operator=(ClQueue&& o) noexcept {
  if (this != &o) {
    if (queue_) clReleaseCommandQueue(queue_);
    queue_ = std::exchange(o.queue_, nullptr);
  }
  return *this;
}

ClBuffer ClBuffer::share() const {
  ClBuffer b;
  if (mem_) cl_check(clRetainMemObject(mem_), "clRetainMemObject");
  b.mem_ = mem_;
  b.bytes_ = bytes_;
  return b;
}

ClBuffer ClContext::buffer(size_t bytes, const void* data, cl_mem_flags flags) const {
  ClBuffer b(context_, bytes, flags);
  if (data && bytes) write(b, 0, bytes, data, true);
  return b;
}

ClBuffer ClContext::shared_buffer(size_t bytes, const void* data) const {
  if (!data || bytes == 0 || !info_.host_unified_memory) return buffer(bytes, data, CL_MEM_READ_ONLY);
  // The kernels only read it: OpenCL's void* is not a licence to write.
  return ClBuffer(context_, bytes, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, const_cast<void*>(data));
}

void queue_write(cl_command_queue q, const ClBuffer& b, size_t offset, size_t bytes, const void* src,
                 bool blocking) {
  if (bytes == 0) return;
  cl_check(clEnqueueWriteBuffer(q, b.get(), blocking ? CL_TRUE : CL_FALSE, offset, bytes, src, 0, nullptr,
                                nullptr),
           "clEnqueueWriteBuffer");
}

void queue_read(cl_command_queue q, const ClBuffer& b, size_t offset, size_t bytes, void* dst) {
  if (bytes == 0) return;
  cl_check(clEnqueueReadBuffer(q, b.get(), CL_TRUE, offset, bytes, dst, 0, nullptr, nullptr),
           "clEnqueueReadBuffer");
}

void queue_finish(cl_command_queue q) { cl_check(clFinish(q), "clFinish"); }

void ClContext::write(const ClBuffer& b, size_t offset, size_t bytes, const void* src, bool blocking) const {
  queue_write(queue(), b, offset, bytes, src, blocking);
}

void ClContext::read(const ClBuffer& b, size_t offset, size_t bytes, void* dst) const {
  queue_read(queue(), b, offset, bytes, dst);
}

void ClContext::finish() const { queue_finish(queue()); }

}  // namespace pmc
