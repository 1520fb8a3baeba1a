// host_link.cpp — map/unmap or staged copies, behind one interface.
#include "gpu/host_link.h"

#include "core/error.h"

namespace pmc {

TransferMode parse_transfer_mode(const std::string& name) {
  if (name == "auto") return TransferMode::Auto;
  if (name == "zero-copy") return TransferMode::ZeroCopy;
  if (name == "copy") return TransferMode::Copy;
  fail_config(setting("transfer"), ": unknown mode '", name, "' (expected auto, zero-copy or copy)");
}

const char* transfer_mode_name(TransferMode mode) {
  switch (mode) {
    case TransferMode::ZeroCopy:
      return "zero-copy";
    case TransferMode::Copy:
      return "copy";
    default:
      return "auto";
  }
}

HostLink::HostLink(const ClContext& cl, TransferMode mode) : HostLink(cl, mode, cl.queue()) {}

HostLink::HostLink(const ClContext& cl, TransferMode mode, cl_command_queue queue) : queue_(queue) {
  zero_copy_ = mode == TransferMode::ZeroCopy ||
               (mode == TransferMode::Auto && (cl.info().host_unified_memory || cl.info().is_cpu));
}

HostLink::~HostLink() {
  // Views still open (an exception between read/write and publish): unmap
  // them so the buffers can be released; errors are moot at this point.
  for (const Pending& p : pending_)
    if (p.mapped) clEnqueueUnmapMemObject(queue_, p.mem, p.ptr, 0, nullptr, nullptr);
  if (!pending_.empty()) clFinish(queue_);
}

void HostLink::staging_too_small(size_t have, size_t need) {
  fail("internal: host staging array of ", have, " elements, ", need, " needed");
}

cl_mem_flags HostLink::buffer_flags() const {
  return CL_MEM_READ_WRITE | (zero_copy_ ? CL_MEM_ALLOC_HOST_PTR : 0);
}

const void* HostLink::read_bytes(const ClBuffer& b, size_t offset, size_t bytes, void* staging,
                                 size_t staging_offset) {
  if (bytes == 0) return staging;
  if (zero_copy_) {
    cl_int st = CL_SUCCESS;
    void* p =
        clEnqueueMapBuffer(queue_, b.get(), CL_TRUE, CL_MAP_READ, offset, bytes, 0, nullptr, nullptr, &st);
    cl_check(st, "clEnqueueMapBuffer(read)");
    pending_.push_back({b.get(), p, offset, bytes, true});
    return p;
  }
  char* dst = static_cast<char*>(staging) + staging_offset;
  cl_check(clEnqueueReadBuffer(queue_, b.get(), CL_TRUE, offset, bytes, dst, 0, nullptr, nullptr),
           "clEnqueueReadBuffer");
  return dst;
}

void* HostLink::write_bytes(const ClBuffer& b, size_t offset, size_t bytes, void* staging,
                            size_t staging_offset) {
  if (bytes == 0) return staging;
  if (zero_copy_) {
    cl_int st = CL_SUCCESS;
    // Write-invalidate: the host overwrites the whole range, nothing is read back.
    void* p = clEnqueueMapBuffer(queue_, b.get(), CL_TRUE, CL_MAP_WRITE_INVALIDATE_REGION, offset, bytes, 0,
                                 nullptr, nullptr, &st);
    cl_check(st, "clEnqueueMapBuffer(write)");
    pending_.push_back({b.get(), p, offset, bytes, true});
    return p;
  }
  char* dst = static_cast<char*>(staging) + staging_offset;
  pending_.push_back({b.get(), dst, offset, bytes, false});
  return dst;
}

void HostLink::publish() {
  for (const Pending& p : pending_) {
    if (p.mapped)
      cl_check(clEnqueueUnmapMemObject(queue_, p.mem, p.ptr, 0, nullptr, nullptr), "clEnqueueUnmapMemObject");
    else  // non-blocking: the staging array outlives the copy (the next blocking read orders it)
      cl_check(clEnqueueWriteBuffer(queue_, p.mem, CL_FALSE, p.offset, p.bytes, p.ptr, 0, nullptr, nullptr),
               "clEnqueueWriteBuffer");
  }
  pending_.clear();
}

}  // namespace pmc
