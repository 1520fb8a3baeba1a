// host_link.h — how the host reads and writes the wave's device buffers.
//
// Between kernel launches the host reads the ray queues the kernels wrote and
// writes the hit records and occlusion bytes the next kernels read. Two ways:
//   zero-copy: the buffers are host-visible (CL_MEM_ALLOC_HOST_PTR) and the
//     host maps them: on a CPU device (PoCL) or an integrated GPU the mapping
//     is the device's own memory, so Embree reads rays and writes hits where
//     the kernels read and write them, with no copies;
//   copy: explicit clEnqueueRead/WriteBuffer through host staging arrays, for
//     discrete GPUs; writes are non-blocking, so the host traces chunk k+1
//     while the device shades chunk k.
// `auto` picks zero-copy for devices that report host-unified memory (every
// CPU device) and copy otherwise; both are tested on PoCL. A view is valid
// until publish(), which unmaps what was mapped (or enqueues the staged
// writes); kernels that use the buffers must be enqueued after it. Every
// command goes to one queue: the context's, or a wave's own (two waves in
// flight, gpu/wavefront_renderer.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "gpu/cl_context.h"

namespace pmc {

enum class TransferMode { Auto, ZeroCopy, Copy };
TransferMode parse_transfer_mode(const std::string& name);  // "auto", "zero-copy" or "copy"
const char* transfer_mode_name(TransferMode mode);

class HostLink {
 public:
  HostLink(const ClContext& cl, TransferMode mode);
  HostLink(const ClContext& cl, TransferMode mode, cl_command_queue queue);
  ~HostLink();
  HostLink(const HostLink&) = delete;
  HostLink& operator=(const HostLink&) = delete;

  bool zero_copy() const { return zero_copy_; }
  // Flags for buffers the host reads or writes through this link.
  cl_mem_flags buffer_flags() const;

  // `staging` (copy mode) must hold at least first + count elements and must
  // not be resized while views into it are open or writes from it pending.
  // Elements [first, first + count) of `b`, as the device last wrote them
  // (blocks until the commands before it finish).
  template <typename T>
  const T* read(const ClBuffer& b, size_t first, size_t count, std::vector<T>& staging) {
    return static_cast<const T*>(read_bytes(b, first * sizeof(T), count * sizeof(T),
                                            staging_for(staging, first + count), first * sizeof(T)));
  }
  // Room for elements [first, first + count) of `b`, which the host fills
  // completely before publish().
  template <typename T>
  T* write(const ClBuffer& b, size_t first, size_t count, std::vector<T>& staging) {
    return static_cast<T*>(write_bytes(b, first * sizeof(T), count * sizeof(T),
                                       staging_for(staging, first + count), first * sizeof(T)));
  }
  // Ends every view handed out since the last publish().
  void publish();

 private:
  // The staging array (copy mode only). It is never resized here: a
  // non-blocking write may still be reading an earlier part of it.
  template <typename T>
  void* staging_for(std::vector<T>& staging, size_t need) const {
    if (zero_copy_) return nullptr;
    if (staging.size() < need) staging_too_small(staging.size(), need);
    return staging.data();
  }
  [[noreturn]] static void staging_too_small(size_t have, size_t need);
  const void* read_bytes(const ClBuffer& b, size_t offset, size_t bytes, void* staging,
                         size_t staging_offset);
  void* write_bytes(const ClBuffer& b, size_t offset, size_t bytes, void* staging, size_t staging_offset);

  struct Pending {
    cl_mem mem;
    void* ptr;
    size_t offset, bytes;
    bool mapped;  // else a staged write to enqueue
  };
  cl_command_queue queue_;
  bool zero_copy_ = false;
  std::vector<Pending> pending_;
};

}  // namespace pmc
