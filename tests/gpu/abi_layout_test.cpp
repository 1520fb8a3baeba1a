// abi_layout_test.cpp — host and OpenCL compilers agree on every shared struct.
//
// The same X-macro lists (core/abi/pmc_layout.h) are expanded on the host and
// inside a kernel that writes sizeof/offsetof values to a buffer; any field
// whose size or offset differs between the C++ and OpenCL compilers fails.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <vector>

#include "core/abi/pmc_layout.h"
#include "core/abi/pmc_types.h"
#include "gpu/program.h"
#include "tests/support/test_support.h"

namespace pmc {
namespace {

TEST(AbiLayout, HostAndKernelAgreeOnSizesAndOffsets) {
  std::vector<std::string> names;
  std::vector<unsigned> host;
#define PMC_HOST_STRUCT(S)       \
  names.push_back("sizeof " #S); \
  host.push_back(unsigned(sizeof(S)));
#define PMC_HOST_FIELD(S, F)              \
  names.push_back("offsetof " #S "." #F); \
  host.push_back(unsigned(offsetof(S, F)));
  PMC_LAYOUT_STRUCTS(PMC_HOST_STRUCT)
  PMC_LAYOUT_FIELDS(PMC_HOST_FIELD)

  const std::string source = R"CL(
#include "pmc_types.h"
#include "pmc_layout.h"
#define PMC_K_STRUCT(S) out[i++] = (uint)sizeof(S);
/* OpenCL C 1.2 has no offsetof: measure with a private instance. */
#define PMC_K_FIELD(S, F) { S tmp_; out[i++] = (uint)((char*)&tmp_.F - (char*)&tmp_); }
__kernel void layout(__global uint* out) {
  if (get_global_id(0) != 0) return;
  int i = 0;
  PMC_LAYOUT_STRUCTS(PMC_K_STRUCT)
  PMC_LAYOUT_FIELDS(PMC_K_FIELD)
}
)CL";
  const ClContext& cl = test::cl();
  ClProgram program = ClProgram::from_text(cl, "abi_layout_test.cl", source);
  ClBuffer out = cl.buffer(host.size() * sizeof(unsigned));
  cl_kernel k = program.kernel("layout");
  set_kernel_args(k, out);
  enqueue_1d(cl.queue(), k, 1);
  std::vector<unsigned> device(host.size());
  cl.read(out, 0, device.size() * sizeof(unsigned), device.data());
  ASSERT_GT(host.size(), 50u);
  for (size_t i = 0; i < host.size(); ++i) EXPECT_EQ(host[i], device[i]) << names[i];
  // The ray record must stay byte-compatible with Embree's RTCRay.
  EXPECT_EQ(sizeof(PmcRay), 48u);
}

}  // namespace
}  // namespace pmc
