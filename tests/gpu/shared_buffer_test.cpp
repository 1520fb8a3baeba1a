// shared_buffer_test.cpp — ClContext::shared_buffer (gpu/cl_context.h), on PoCL.
//
// On a host-unified device the buffer is the caller's memory itself
// (CL_MEM_USE_HOST_PTR, the same address), elsewhere a copy; either way the
// device reads the same bytes, and empty data gets an ordinary buffer.
#include <gtest/gtest.h>

#include <numeric>
#include <vector>

#include "gpu/cl_context.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

TEST(SharedBuffer, IsTheHostMemoryOnUnifiedDevices) {
  const ClContext& cl = test::cl();
  std::vector<uint32_t> data(4096);
  std::iota(data.begin(), data.end(), 7u);
  ClBuffer b = cl.shared_buffer_of(data);
  cl_mem_flags flags = 0;
  void* host = nullptr;
  ASSERT_EQ(clGetMemObjectInfo(b.get(), CL_MEM_FLAGS, sizeof(flags), &flags, nullptr), CL_SUCCESS);
  ASSERT_EQ(clGetMemObjectInfo(b.get(), CL_MEM_HOST_PTR, sizeof(host), &host, nullptr), CL_SUCCESS);
  if (cl.info().host_unified_memory) {
    EXPECT_TRUE(flags & CL_MEM_USE_HOST_PTR);
    EXPECT_EQ(host, static_cast<void*>(data.data()));
  } else {
    EXPECT_FALSE(flags & CL_MEM_USE_HOST_PTR);
  }
  EXPECT_TRUE(flags & CL_MEM_READ_ONLY);
  std::vector<uint32_t> back(data.size());
  cl.read(b, 0, back.size() * sizeof(uint32_t), back.data());
  EXPECT_EQ(back, data);
  // Empty data: an ordinary (copied, at least 16-byte) buffer.
  ClBuffer e = cl.shared_buffer_of(std::vector<uint32_t>{});
  ASSERT_EQ(clGetMemObjectInfo(e.get(), CL_MEM_FLAGS, sizeof(flags), &flags, nullptr), CL_SUCCESS);
  EXPECT_FALSE(flags & CL_MEM_USE_HOST_PTR);
}

}  // namespace
}  // namespace pmc
