// cl_context.h — the only place that talks to the OpenCL runtime directly.
//
// Picks a platform/device (a name substring from the device setting, else the first GPU,
// else the first CPU device such as PoCL), and wraps the handful of objects the
// renderer needs (context, in-order queue with profiling, buffers, programs,
// kernels) in small RAII types. Every call is checked; failures become
// pmc::Error with the call's name and the OpenCL error code.
#pragma once

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace pmc {

struct ClDeviceInfo {
  std::string platform;
  std::string name;
  bool is_gpu = false;
  bool is_cpu = false;
  bool host_unified_memory = false;  // device memory is host memory (CPU devices, integrated GPUs)
  std::string version;
  size_t global_memory = 0;
  unsigned compute_units = 0;
  cl_platform_id platform_id = nullptr;
  cl_device_id device_id = nullptr;
};

// All devices of all platforms. Throws pmc::Error (with install advice) when
// there is no OpenCL platform at all.
std::vector<ClDeviceInfo> list_cl_devices();
// A device's string property (CL_DRIVER_VERSION, ...); empty when the driver has none.
std::string cl_device_string(cl_device_id d, cl_device_info what);

void cl_check(cl_int status, const char* what);

class ClBuffer {
 public:
  ClBuffer() = default;
  ClBuffer(cl_context ctx, size_t bytes, cl_mem_flags flags = CL_MEM_READ_WRITE, void* host = nullptr);
  ~ClBuffer();
  ClBuffer(ClBuffer&& o) noexcept : mem_(std::exchange(o.mem_, nullptr)), bytes_(o.bytes_) {}
  ClBuffer& operator=(ClBuffer&& o) noexcept;
  ClBuffer(const ClBuffer&) = delete;
  ClBuffer& operator=(const ClBuffer&) = delete;
  cl_mem get() const { return mem_; }
  size_t bytes() const { return bytes_; }
  // Another handle to the same memory (one more reference): buffers that
  // several waves in flight share (the film, the cache table).
  ClBuffer share() const;

 private:
  cl_mem mem_ = nullptr;
  size_t bytes_ = 0;
};

// An in-order command queue with profiling. A context has one; a render
// with two waves in flight gives the second its own, so that the host's
// blocking maps and reads of one wave wait for that wave's commands only.
class ClQueue {
 public:
  ClQueue() = default;
  ClQueue(cl_context ctx, cl_device_id device);
  ~ClQueue();
  ClQueue(ClQueue&& o) noexcept : queue_(std::exchange(o.queue_, nullptr)) {}
  ClQueue& operator=(ClQueue&& o) noexcept;
  ClQueue(const ClQueue&) = delete;
  ClQueue& operator=(const ClQueue&) = delete;
  cl_command_queue get() const { return queue_; }

 private:
  cl_command_queue queue_ = nullptr;
};

// Checked transfers and waits on a given queue (ClContext's own use its queue).
void queue_write(cl_command_queue q, const ClBuffer& b, size_t offset, size_t bytes, const void* src,
                 bool blocking);
void queue_read(cl_command_queue q, const ClBuffer& b, size_t offset, size_t bytes, void* dst);  // blocking
void queue_finish(cl_command_queue q);

class ClContext {
 public:
  // `device_filter`: case-insensitive substring of the device or platform name; "" = default choice.
  explicit ClContext(const std::string& device_filter = "");
  ~ClContext();
  ClContext(const ClContext&) = delete;
  ClContext& operator=(const ClContext&) = delete;

  cl_context context() const { return context_; }
  cl_command_queue queue() const { return queue_.get(); }
  ClQueue new_queue() const { return ClQueue(context_, info_.device_id); }
  cl_device_id device() const { return info_.device_id; }
  const ClDeviceInfo& info() const { return info_; }
  std::string description() const { return info_.name + " (" + info_.platform + ")"; }

  // Buffer with `bytes` (at least 1) and optional initial contents (blocking copy).
  ClBuffer buffer(size_t bytes, const void* data = nullptr, cl_mem_flags flags = CL_MEM_READ_WRITE) const;
  template <typename T>
  ClBuffer buffer_of(const std::vector<T>& v, cl_mem_flags flags = CL_MEM_READ_ONLY) const {
    return buffer(v.size() * sizeof(T), v.empty() ? nullptr : v.data(), flags);
  }
  // A read-only buffer of the `bytes` at `data`, which the caller keeps alive
  // and unchanged for the buffer's lifetime. On devices with host-unified
  // memory (CPU devices, integrated GPUs) it is that memory itself
  // (CL_MEM_USE_HOST_PTR: no allocation, no copy); on others (discrete GPUs)
  // the bytes are copied to the device, as buffer() does.
  ClBuffer shared_buffer(size_t bytes, const void* data) const;
  template <typename T, typename A>
  ClBuffer shared_buffer_of(const std::vector<T, A>& v) const {
    return shared_buffer(v.size() * sizeof(T), v.empty() ? nullptr : v.data());
  }
  void write(const ClBuffer& b, size_t offset, size_t bytes, const void* src, bool blocking) const;
  void read(const ClBuffer& b, size_t offset, size_t bytes, void* dst) const;  // blocking
  void finish() const;

 private:
  ClDeviceInfo info_;
  cl_context context_ = nullptr;
  ClQueue queue_;
};

}  // namespace pmc
