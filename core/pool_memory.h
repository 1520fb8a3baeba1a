// pool_memory.h — memory for large tables the kernels read (texel pools, sky maps).
//
// Blocks of 2 MiB and more are 2 MiB-aligned (host pointers that CPU
// devices use as buffer memory, ClContext::shared_buffer_of: no device
// copy), and a PoolVector's elements are left uninitialised by resize
// (whoever fills it writes every element). They are not advised into
// transparent huge pages any more: on the shared 2-core machine a
// huge-page fault waited for the kernel to compact memory whenever its
// free 2 MiB blocks were gone (Sponza's 161 MB texel pool read back from
// the texture cache took 0.05-0.24 s that way, 0.08 s without), and
// renders were no faster (docs/BENCHMARKS.md, "Shade kernel: ns per hit",
// session 42).
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <utility>
#include <vector>

namespace pmc {

// `bytes` of memory (2 MiB-aligned from 2 MiB on), freed with std::free.
void* allocate_pool_bytes(size_t bytes);

// An allocator that leaves value-initialised elements uninitialised (resize
// without a memset) and takes its memory from allocate_pool_bytes.
template <typename T>
struct NoInitAllocator {
  using value_type = T;
  template <typename U>
  struct rebind {
    using other = NoInitAllocator<U>;
  };
  NoInitAllocator() = default;
  template <typename U>
  NoInitAllocator(const NoInitAllocator<U>&) noexcept {}
  T* allocate(size_t n) {
    if (n > size_t(-1) / sizeof(T)) throw std::bad_alloc();
    return static_cast<T*>(allocate_pool_bytes(n * sizeof(T)));
  }
  void deallocate(T* p, size_t) noexcept { std::free(p); }
  template <typename U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  template <typename U>
  bool operator==(const NoInitAllocator<U>&) const noexcept {
    return true;
  }
  template <typename U>
  bool operator!=(const NoInitAllocator<U>&) const noexcept {
    return false;
  }
};

template <typename T>
using PoolVector = std::vector<T, NoInitAllocator<T>>;

}  // namespace pmc
