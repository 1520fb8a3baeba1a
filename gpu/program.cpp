// program.cpp — include expansion, program build with logs, 1-D launches.
#include "gpu/program.h"

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <utility>

#include "core/error.h"
#include "gpu/embedded_sources.h"

namespace pmc {
namespace {

std::string read_disk_source(const std::string& root, const std::string& name) {
  for (const char* dir : {"/core/abi/", "/core/device/", "/gpu/kernels/"}) {
    std::ifstream in(root + dir + name);
    if (in) {
      std::ostringstream os;
      os << in.rdbuf();
      return os.str();
    }
  }
  fail("PMC_KERNEL_DIR=", root, ": kernel source '", name,
       "' not found under core/abi, core/device or gpu/kernels");
}

void expand_text(const std::string& name, const std::string& text, std::set<std::string>& seen,
                 std::ostringstream& out);

void expand(const std::string& name, std::set<std::string>& seen, std::ostringstream& out) {
  if (!seen.insert(name).second) return;  // every file is included once
  expand_text(name, kernel_source_file(name), seen, out);
}

void expand_text(const std::string& name, const std::string& text, std::set<std::string>& seen,
                 std::ostringstream& out) {
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  out << "#line 1 \"" << name << "\"\n";
  while (std::getline(in, line)) {
    ++line_no;
    size_t first = line.find_first_not_of(" \t");
    if (first != std::string::npos && line.compare(first, 8, "#include") == 0) {
      size_t q0 = line.find('"');
      size_t q1 = q0 == std::string::npos ? q0 : line.find('"', q0 + 1);
      if (q1 != std::string::npos) {
        // Files are known by base name ("../abi/pmc_vec.h" is pmc_vec.h): the
        // relative path is for the C++ compiler, which reads them in place.
        std::string included = line.substr(q0 + 1, q1 - q0 - 1);
        expand(included.substr(included.find_last_of('/') + 1), seen, out);
        out << "#line " << line_no + 1 << " \"" << name << "\"\n";
        continue;
      }
    }
    out << line << '\n';
  }
}

}  // namespace

std::string kernel_source_file(const std::string& name) {
  if (const char* root = std::getenv("PMC_KERNEL_DIR"); root && *root) return read_disk_source(root, name);
  for (const EmbeddedSource* s = embedded_sources(); s->name; ++s)
    if (name == s->name) return s->text;
  fail("kernel source '", name, "' is not embedded in this binary");
}

std::string expand_kernel_source(const std::string& name) {
  std::set<std::string> seen;
  std::ostringstream out;
  expand(name, seen, out);
  return out.str();
}

std::string expand_kernel_text(const std::string& name, const std::string& text) {
  std::set<std::string> seen{name};
  std::ostringstream out;
  expand_text(name, text, seen, out);
  return out.str();
}

std::string kernel_code_of(const std::string& source) {
  enum { Code, Line, Block, Str, Chr } state = Code;
  std::string flat;  // comments gone (one space each), runs of blanks one space
  flat.reserve(source.size());
  auto blank = [&flat] {
    if (!flat.empty() && flat.back() != ' ' && flat.back() != '\n') flat += ' ';
  };
  for (size_t i = 0; i < source.size(); ++i) {
    const char c = source[i], next = i + 1 < source.size() ? source[i + 1] : '\0';
    switch (state) {
      case Code:
        if (c == '/' && next == '/') {
          state = Line, ++i;
        } else if (c == '/' && next == '*') {
          state = Block, ++i, blank();
        } else if (c == ' ' || c == '\t' || c == '\r') {
          blank();
        } else {
          if (c == '"') state = Str;
          if (c == '\'') state = Chr;
          flat += c;
        }
        break;
      case Line:
        if (c == '\n') state = Code, flat += c;
        break;
      case Block:
        if (c == '*' && next == '/')
          state = Code, ++i;
        else if (c == '\n')
          flat += c;
        break;
      case Str:
      case Chr:
        flat += c;
        if (c == '\\' && next != '\0')
          flat += next, ++i;
        else if (c == (state == Str ? '"' : '\''))
          state = Code;
        break;
    }
  }
  std::istringstream in(flat);
  std::string line, out;
  while (std::getline(in, line)) {
    const size_t first = line.find_first_not_of(' ');
    if (first == std::string::npos || line.compare(first, 5, "#line") == 0) continue;
    const size_t last = line.find_last_not_of(' ');
    out.append(line, first, last - first + 1);
    out += '\n';
  }
  return out;
}

ClProgram::ClProgram(const ClContext& ctx, const std::string& main_file, const std::string& options) {
  build(ctx, main_file, expand_kernel_source(main_file), options);
}

ClProgram ClProgram::from_text(const ClContext& ctx, const std::string& name, const std::string& text,
                               const std::string& options) {
  ClProgram p;
  p.build(ctx, name, expand_kernel_text(name, text), options);
  return p;
}

ClProgram::ClProgram(ClProgram&& o) noexcept
    : program_(std::exchange(o.program_, nullptr)),
      kernels_(std::move(o.kernels_)),
      build_seconds_(o.build_seconds_) {
  o.kernels_.clear();
}

void ClProgram::build(const ClContext& ctx, const std::string& main_file, const std::string& src,
                      const std::string& options) {
  auto t0 = std::chrono::steady_clock::now();
  const char* text = src.c_str();
  size_t len = src.size();
  cl_int st = CL_SUCCESS;
  program_ = clCreateProgramWithSource(ctx.context(), 1, &text, &len, &st);
  cl_check(st, "clCreateProgramWithSource");
  std::string opts = "-cl-std=CL1.2 " + options;
  if (const char* extra = std::getenv("PMC_CL_BUILD_OPTIONS"); extra && *extra)
    opts += std::string(" ") + extra;
  cl_device_id dev = ctx.device();
  st = clBuildProgram(program_, 1, &dev, opts.c_str(), nullptr, nullptr);
  if (st != CL_SUCCESS) {
    std::string log = build_log(dev);
    clReleaseProgram(program_);
    program_ = nullptr;
    fail("OpenCL: building ", main_file, " for ", ctx.description(), " failed (error ", st, "):\n", log);
  }
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (const char* dir = std::getenv("PMC_CL_DUMP_DIR"); dir && *dir) dump_build(dev, dir, main_file, opts);
}

std::string ClProgram::build_log(cl_device_id dev) const {
  size_t n = 0;
  clGetProgramBuildInfo(program_, dev, CL_PROGRAM_BUILD_LOG, 0, nullptr, &n);
  std::string log(n, '\0');
  clGetProgramBuildInfo(program_, dev, CL_PROGRAM_BUILD_LOG, n, log.data(), nullptr);
  while (!log.empty() && log.back() == '\0') log.pop_back();
  return log;
}

void ClProgram::dump_build(cl_device_id dev, const std::string& dir, const std::string& main_file,
                           const std::string& opts) const {
  static std::atomic<int> serial{0};  // programs may build on several threads
  std::string base = main_file;
  for (char& c : base)
    if (c == '/') c = '_';
  std::string stem = dir + "/" + base + "-" + std::to_string(++serial);
  std::ofstream(stem + ".log") << "options: " << opts << "\n" << build_log(dev);
  size_t size = 0;
  if (clGetProgramInfo(program_, CL_PROGRAM_BINARY_SIZES, sizeof size, &size, nullptr) != CL_SUCCESS ||
      size == 0)
    return;
  std::string binary(size, '\0');
  unsigned char* p = reinterpret_cast<unsigned char*>(binary.data());
  if (clGetProgramInfo(program_, CL_PROGRAM_BINARIES, sizeof p, &p, nullptr) == CL_SUCCESS)
    std::ofstream(stem + ".bin", std::ios::binary) << binary;
}

ClProgram::~ClProgram() {
  for (auto& kv : kernels_) clReleaseKernel(kv.second);
  if (program_) clReleaseProgram(program_);
}

ClProgram ClProgram::share() const {
  ClProgram p;
  if (program_) cl_check(clRetainProgram(program_), "clRetainProgram");
  p.program_ = program_;
  p.build_seconds_ = build_seconds_;
  return p;
}

cl_kernel ClProgram::kernel(const std::string& name) {
  auto it = kernels_.find(name);
  if (it != kernels_.end()) return it->second;
  cl_int st = CL_SUCCESS;
  cl_kernel k = clCreateKernel(program_, name.c_str(), &st);
  if (st != CL_SUCCESS) fail("OpenCL: kernel '", name, "' not found in program (error ", st, ")");
  kernels_[name] = k;
  return k;
}

void check_kernel_arg_count(cl_kernel k, cl_uint given) {
  cl_uint expected = 0;
  clGetKernelInfo(k, CL_KERNEL_NUM_ARGS, sizeof(expected), &expected, nullptr);
  if (expected != given) {
    char name[128] = {0};
    clGetKernelInfo(k, CL_KERNEL_FUNCTION_NAME, sizeof(name) - 1, name, nullptr);
    fail("internal: kernel '", name, "' takes ", expected, " arguments, the host passes ", given);
  }
}

void enqueue_1d(cl_command_queue q, cl_kernel k, size_t count, cl_event* event) {
  if (count == 0) return;
  const size_t local = 64;
  size_t global = (count + local - 1) / local * local;
  cl_check(clEnqueueNDRangeKernel(q, k, 1, nullptr, &global, &local, 0, nullptr, event),
           "clEnqueueNDRangeKernel");
}

}  // namespace pmc
