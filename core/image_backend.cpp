// image_backend.cpp — finding and loading the image plugin (core/image_backend.h).
#include "core/image_backend.h"

#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <cstdlib>
#include <future>
#include <mutex>
#include <thread>

#include "core/error.h"

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

// The load runs on a thread of its own, not a TBB task: it is the dynamic
// loader's work (not compute), and --threads 1 must not serialise it.
struct Loader {
  std::once_flag started;
  std::shared_future<ImageBackend*> backend;
  std::thread thread;
  ~Loader() {
    if (thread.joinable()) thread.join();
  }
};

Loader& loader() {
  static Loader l;
  return l;
}

}  // namespace

void preload_image_backend() {
  Loader& l = loader();
  std::call_once(l.started, [&l] {
    std::packaged_task<ImageBackend*()> task(load_plugin);
    l.backend = task.get_future().share();
    l.thread = std::thread(std::move(task));
  });
}

ImageBackend& image_backend() {
  preload_image_backend();
  return *loader().backend.get();
}

}  // namespace pmc
