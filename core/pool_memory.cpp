// pool_memory.cpp — large blocks, 2 MiB-aligned.
#include "core/pool_memory.h"

namespace pmc {

void* allocate_pool_bytes(size_t bytes) {
  constexpr size_t kAlign = size_t(2) << 20;
  if (bytes < kAlign) {
    void* p = std::malloc(bytes ? bytes : 1);
    if (!p) throw std::bad_alloc();
    return p;
  }
  void* p = std::aligned_alloc(kAlign, (bytes + kAlign - 1) / kAlign * kAlign);
  if (!p) throw std::bad_alloc();
  return p;
}

}  // namespace pmc
