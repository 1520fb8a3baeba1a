// denoiser.cpp — OIDN loaded at run time; the RT filter with albedo and normal (and their prefilters).
#include "core/denoiser.h"

#include <dlfcn.h>
#include <glob.h>

#include <chrono>
#include <cstdlib>
#include <mutex>
#include <vector>

#include "core/error.h"

namespace pmc {
namespace {

// OIDN 2.x's C API (include/OpenImageDenoise/oidn.h): the handles are
// opaque pointers, the enums plain ints with these values.
using OidnDevice = void*;
using OidnFilter = void*;
using OidnBuffer = void*;
constexpr int kOidnDeviceTypeDefault =
    0;                                // OIDN_DEVICE_TYPE_DEFAULT: a GPU if one is supported, else the CPU
constexpr int kOidnErrorNone = 0;     // OIDN_ERROR_NONE
constexpr int kOidnFormatFloat3 = 3;  // OIDN_FORMAT_FLOAT3
const char* const kOidnDeviceTypes[] = {"default", "CPU", "SYCL", "CUDA", "HIP", "Metal"};

struct Oidn {
  OidnDevice (*new_device)(int type);
  void (*commit_device)(OidnDevice);
  void (*release_device)(OidnDevice);
  int (*get_device_error)(OidnDevice, const char** message);
  int (*get_device_int)(OidnDevice, const char* name);
  OidnBuffer (*new_buffer)(OidnDevice, size_t bytes);
  void (*write_buffer)(OidnBuffer, size_t offset, size_t bytes, const void* src);
  void (*read_buffer)(OidnBuffer, size_t offset, size_t bytes, void* dst);
  void (*release_buffer)(OidnBuffer);
  OidnFilter (*new_filter)(OidnDevice, const char* type);
  void (*set_filter_image)(OidnFilter, const char* name, OidnBuffer, int format, size_t width, size_t height,
                           size_t byte_offset, size_t pixel_stride, size_t row_stride);
  void (*set_filter_bool)(OidnFilter, const char* name, bool value);
  void (*commit_filter)(OidnFilter);
  void (*execute_filter)(OidnFilter);
  void (*release_filter)(OidnFilter);
};

std::vector<std::string> library_candidates() {
  if (const char* env = std::getenv("PMC_OIDN_LIBRARY"); env && *env) return {env};
  std::vector<std::string> out;
#ifdef PMC_SOURCE_DIR
  glob_t g{};
  const std::string pattern = std::string(PMC_SOURCE_DIR) +
                              "/.venv/lib/python3*/site-packages/pyoidn/oidn/lib/libOpenImageDenoise.so.2";
  if (glob(pattern.c_str(), 0, nullptr, &g) == 0)
    for (size_t i = 0; i < g.gl_pathc; ++i) out.push_back(g.gl_pathv[i]);
  else
    out.push_back(pattern);
  globfree(&g);
#endif
  out.push_back("libOpenImageDenoise.so.2");
  return out;
}

// The loaded library's functions, or null with `why` (every place tried).
const Oidn* load_oidn(std::string& why) {
  static std::once_flag once;
  static Oidn oidn;
  static bool ok = false;
  static std::string error;
  std::call_once(once, [] {
    std::string tried;
    void* lib = nullptr;
    for (const std::string& path : library_candidates()) {
      lib = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (lib) break;
      const char* e = dlerror();
      tried += "\n  " + path + ": " + (e ? e : "cannot load");
    }
    if (!lib) {
      error =
          "Intel Open Image Denoise (libOpenImageDenoise.so.2) not found; install it with scripts/setup "
          "(the PyPI package pyoidn in .venv) or name the library in PMC_OIDN_LIBRARY. Tried:" +
          tried;
      return;
    }
    std::string missing;
    auto sym = [&](auto& fn, const char* name, const char* older = nullptr) {
      void* p = dlsym(lib, name);
      if (!p && older) p = dlsym(lib, older);
      if (!p) missing += std::string(missing.empty() ? "" : ", ") + name;
      fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(p);
    };
    sym(oidn.new_device, "oidnNewDevice");
    sym(oidn.commit_device, "oidnCommitDevice");
    sym(oidn.release_device, "oidnReleaseDevice");
    sym(oidn.get_device_error, "oidnGetDeviceError");
    sym(oidn.get_device_int, "oidnGetDeviceInt", "oidnGetDevice1i");
    sym(oidn.new_buffer, "oidnNewBuffer");
    sym(oidn.write_buffer, "oidnWriteBuffer");
    sym(oidn.read_buffer, "oidnReadBuffer");
    sym(oidn.release_buffer, "oidnReleaseBuffer");
    sym(oidn.new_filter, "oidnNewFilter");
    sym(oidn.set_filter_image, "oidnSetFilterImage");
    sym(oidn.set_filter_bool, "oidnSetFilterBool", "oidnSetFilter1b");
    sym(oidn.commit_filter, "oidnCommitFilter");
    sym(oidn.execute_filter, "oidnExecuteFilter");
    sym(oidn.release_filter, "oidnReleaseFilter");
    if (!missing.empty()) {
      error = "the Open Image Denoise library lacks " + missing + " (pmc needs OIDN 2.x)";
      return;
    }
    ok = true;
  });
  why = error;
  return ok ? &oidn : nullptr;
}

// Fails with the device's pending error, if any.
void check(const Oidn& o, OidnDevice device, const char* what) {
  const char* message = nullptr;
  if (o.get_device_error(device, &message) != kOidnErrorNone)
    fail("Open Image Denoise: ", what, ": ", message ? message : "unknown error");
}

// Device objects released in reverse order of creation.
struct Scope {
  const Oidn& o;
  OidnDevice device = nullptr;
  std::vector<OidnBuffer> buffers;
  std::vector<OidnFilter> filters;
  ~Scope() {
    for (OidnFilter f : filters) o.release_filter(f);
    for (OidnBuffer b : buffers) o.release_buffer(b);
    if (device) o.release_device(device);
  }
};

}  // namespace

bool denoiser_available(std::string* why) {
  std::string w;
  const bool ok = load_oidn(w) != nullptr;
  if (why) *why = w;
  return ok;
}

DenoiseResult denoise(const DenoiseInputs& in) {
  std::string why;
  const Oidn* loaded = load_oidn(why);
  if (!loaded) fail(why);
  const Oidn& o = *loaded;
  const Image& color = *in.color;
  const int w = color.width, h = color.height;
  for (const Image* im : {in.color, in.albedo, in.normal})
    PMC_CHECK(im && im->width == w && im->height == h && im->channels == 3, "denoise inputs' sizes");
  const size_t bytes = size_t(w) * size_t(h) * 3 * sizeof(float);

  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  Scope s{o};
  s.device = o.new_device(kOidnDeviceTypeDefault);
  check(o, s.device, "creating the device");
  o.commit_device(s.device);
  check(o, s.device, "committing the device");
  DenoiseResult result;
  const int type = o.get_device_int(s.device, "type");
  result.device = type >= 0 && type < 6 ? kOidnDeviceTypes[type] : "type " + std::to_string(type);

  auto buffer = [&](const Image* im) {
    OidnBuffer b = o.new_buffer(s.device, bytes);
    check(o, s.device, "allocating a buffer");
    s.buffers.push_back(b);
    if (im) o.write_buffer(b, 0, bytes, im->pixels.data());
    return b;
  };
  OidnBuffer color_b = buffer(in.color), albedo_b = buffer(in.albedo), normal_b = buffer(in.normal);
  OidnBuffer output_b = buffer(nullptr);
  auto filter = [&](std::initializer_list<std::pair<const char*, OidnBuffer>> images, OidnBuffer out,
                    bool clean_aux) {
    OidnFilter f = o.new_filter(s.device, "RT");
    check(o, s.device, "creating the RT filter");
    s.filters.push_back(f);
    for (const auto& [name, b] : images)
      o.set_filter_image(f, name, b, kOidnFormatFloat3, size_t(w), size_t(h), 0, 0, 0);
    o.set_filter_image(f, "output", out, kOidnFormatFloat3, size_t(w), size_t(h), 0, 0, 0);
    if (images.size() == 3) {
      o.set_filter_bool(f, "hdr", true);
      o.set_filter_bool(f, "cleanAux", clean_aux);
    }
    o.commit_filter(f);
    check(o, s.device, "committing the filter");
    o.execute_filter(f);
    check(o, s.device, "denoising");
  };
  if (in.prefilter_aux) {  // the aux images denoised in place, then cleanAux
    filter({{"albedo", albedo_b}}, albedo_b, false);
    filter({{"normal", normal_b}}, normal_b, false);
  }
  filter({{"color", color_b}, {"albedo", albedo_b}, {"normal", normal_b}}, output_b, in.prefilter_aux);
  result.image.width = w;
  result.image.height = h;
  result.image.channels = 3;
  result.image.pixels.resize(size_t(w) * size_t(h) * 3);
  o.read_buffer(output_b, 0, bytes, result.image.pixels.data());
  check(o, s.device, "reading the output");
  result.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return result;
}

}  // namespace pmc
