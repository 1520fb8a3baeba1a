// program.h — OpenCL programs from sources embedded in the binary.
//
// At build time CMake embeds every core/abi/*.h, core/device/*.h and
// gpu/kernels/*.cl file (gpu/embed_sources.cmake). At run time the quoted #includes are expanded
// here (by base name), with #line directives so compiler messages name the right file and
// line; set PMC_KERNEL_DIR=<repository root> to read the files from disk
// instead while developing. A failed build throws pmc::Error carrying the
// compiler's log. For profiling, PMC_CL_BUILD_OPTIONS adds build options
// (-cl-nv-verbose: NVIDIA's register and spill counts) and PMC_CL_DUMP_DIR=DIR
// writes each program's log and binary (PTX on NVIDIA) there.
#pragma once

#include <map>
#include <string>

#include "gpu/cl_context.h"

namespace pmc {

// Source text of an embedded (or, with PMC_KERNEL_DIR, on-disk) file by base name.
std::string kernel_source_file(const std::string& name);
// `name` with all quoted includes expanded, #line-annotated.
std::string expand_kernel_source(const std::string& name);
// In-memory source `text` (reported as `name`) with its quoted includes expanded.
std::string expand_kernel_text(const std::string& name, const std::string& text);
// The code of (expanded) kernel source: comments, #line markers and blank
// lines dropped, each run of spaces and tabs outside string and character
// literals one space, lines trimmed. Two sources that differ only in
// comments, layout or where their files start read the same.
std::string kernel_code_of(const std::string& source);

class ClProgram {
 public:
  ClProgram(const ClContext& ctx, const std::string& main_file, const std::string& options = "");
  // A program from in-memory source (tests, generated kernels); `name` labels errors.
  static ClProgram from_text(const ClContext& ctx, const std::string& name, const std::string& text,
                             const std::string& options = "");
  ClProgram(ClProgram&& o) noexcept;
  ~ClProgram();
  ClProgram(const ClProgram&) = delete;
  ClProgram& operator=(const ClProgram&) = delete;
  cl_kernel kernel(const std::string& name);  // created once, owned by the program
  // The same built program with kernel objects of its own: a kernel's
  // arguments are state, so two host threads launching one kernel need two.
  ClProgram share() const;
  double build_seconds() const { return build_seconds_; }

 private:
  ClProgram() = default;
  void build(const ClContext& ctx, const std::string& name, const std::string& expanded,
             const std::string& options);
  std::string build_log(cl_device_id dev) const;
  void dump_build(cl_device_id dev, const std::string& dir, const std::string& main_file,
                  const std::string& opts) const;
  cl_program program_ = nullptr;
  std::map<std::string, cl_kernel> kernels_;
  double build_seconds_ = 0.0;
};

// Typed argument setting: set_kernel_args(k, buffer, 3u, frame_buffer ...).
inline void set_kernel_arg(cl_kernel k, cl_uint index, const ClBuffer& b) {
  cl_mem m = b.get();
  cl_int st = clSetKernelArg(k, index, sizeof(cl_mem), &m);
  if (st != CL_SUCCESS) cl_check(st, ("clSetKernelArg(buffer #" + std::to_string(index) + ")").c_str());
}
template <typename T>
void set_kernel_arg(cl_kernel k, cl_uint index, const T& value) {
  static_assert(std::is_trivially_copyable<T>::value, "kernel arguments are plain values");
  cl_int st = clSetKernelArg(k, index, sizeof(T), &value);
  if (st != CL_SUCCESS) cl_check(st, ("clSetKernelArg(value #" + std::to_string(index) + ")").c_str());
}
void check_kernel_arg_count(cl_kernel k, cl_uint given);
template <typename... Args>
void set_kernel_args(cl_kernel k, const Args&... args) {
  check_kernel_arg_count(k, cl_uint(sizeof...(Args)));
  cl_uint i = 0;
  (set_kernel_arg(k, i++, args), ...);
}

// Enqueue a 1-D range [0, count) rounded up to the local size, with no global
// offset (PoCL compiles a separate work-group function for offsets);
// kernels bound-check their index. Returns the event (caller releases) if asked.
void enqueue_1d(cl_command_queue q, cl_kernel k, size_t count, cl_event* event = nullptr);

}  // namespace pmc
