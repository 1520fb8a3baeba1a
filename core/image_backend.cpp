// image_backend.cpp — finding and loading the image plugin (core/image_backend.h).
#include "core/image_backend.h"

#include <dlfcn.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "core/error.h"
#include "core/native_images.h"

// Defined only where the backend is linked in (the fuzz targets).
extern "C" pmc::ImageBackend* pmc_image_backend_v1() __attribute__((weak));

namespace pmc {

int ImageHeader::channel_index(const std::string& name) const {
  for (size_t c = 0; c < channel_names.size(); ++c)
    if (channel_names[c] == name) return int(c);
  return -1;
}

namespace {

constexpr const char* kPluginFile = "libpmc_oiio.so";

std::string executable_folder() {
  char buf[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof(buf) - 1);
  if (n <= 0) return {};
  std::string exe(buf, size_t(n));
  const size_t slash = exe.rfind('/');
  return slash == std::string::npos ? std::string() : exe.substr(0, slash);
}

ImageBackend* load_plugin() {
  if (pmc_image_backend_v1) return pmc_image_backend_v1();
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("PMC_IMAGE_PLUGIN"); env && *env) {
    candidates.push_back(env);  // an explicit choice is the only one tried
  } else {
    const std::string dir = executable_folder();
    if (!dir.empty()) {
      candidates.push_back(dir + "/" + kPluginFile);
      candidates.push_back(dir + "/../lib/pmc/" + kPluginFile);
    }
    candidates.push_back(kPluginFile);
  }
  std::string tried;
  for (const std::string& path : candidates) {
    const bool by_path = path.find('/') != std::string::npos;
    if (by_path && access(path.c_str(), F_OK) != 0) {
      tried += "\n  " + path + ": no such file";
      continue;
    }
    void* lib = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
      const char* why = dlerror();
      tried += "\n  " + path + ": " + (why ? why : "cannot be loaded");
      continue;
    }
    using Entry = ImageBackend* (*)();
    auto entry = reinterpret_cast<Entry>(dlsym(lib, "pmc_image_backend_v1"));
    if (!entry) {
      tried += "\n  " + path + ": not a pmc image plugin (no pmc_image_backend_v1)";
      continue;
    }
    return entry();  // never unloaded: the backend lives as long as the process
  }
  fail("cannot load the image plugin ", kPluginFile,
       " (pmc reads and writes images through it; build it with ",
       "pmc, or set PMC_IMAGE_PLUGIN to its path). Tried:", tried);
}

// Native formats first (core/native_images.h); the plugin for the rest,
// loaded the first time a file needs it.
class Images final : public ImageBackend {
 public:
  std::unique_ptr<ImageReader> open(const std::string& path, bool unassociated_alpha,
                                    std::string& why) override {
    auto native = open_native_image(path, unassociated_alpha, why);
    if (native || !why.empty()) return native;
    if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
      std::fclose(f);
    } else {  // a missing file is reported as missing, whether or not the plugin loads
      why = std::strerror(errno);
      return nullptr;
    }
    return plugin_for(path, "reading").open(path, unassociated_alpha, why);
  }
  bool write(const std::string& file, const std::string& format_path, const ImageWrite& image,
             std::string& why) override {
    if (native_image_writes(format_path, image)) return write_native_image(file, format_path, image, why);
    return plugin_for(format_path, "writing").write(file, format_path, image, why);
  }

 private:
  ImageBackend& plugin() {
    std::call_once(loaded_, [this] { plugin_ = load_plugin(); });  // tried again after a throw
    return *plugin_;
  }
  // The plugin, or an error that names the file that needed it.
  ImageBackend& plugin_for(const std::string& path, const char* action) {
    try {
      return plugin();
    } catch (const Error& e) {
      fail(path, ": ", action,
           " this file needs the image plugin (pmc reads only OpenEXR, 8-bit PNG, JPEG and Radiance HDR "
           "itself): ",
           e.what());
    }
  }
  std::once_flag loaded_;
  ImageBackend* plugin_ = nullptr;
};

}  // namespace

ImageBackend& image_backend() {
  static Images images;
  return images;
}

}  // namespace pmc
