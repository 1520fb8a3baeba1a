// atomic_write.cpp — temporary name, write, rename.
#include "core/atomic_write.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/error.h"

namespace pmc {

void write_atomically(const std::string& path, const std::function<void(const std::string& tmp)>& write) {
  std::filesystem::path tmp(path);
  tmp.replace_filename(tmp.stem().string() + ".tmp" + std::to_string(::getpid()) + tmp.extension().string());
  try {
    write(tmp.string());
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    fail(path, ": cannot move the finished file into place");
  }
}

void write_text_file(const std::string& path, const std::string& text) {
  write_atomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) fail(path, ": cannot open for writing");
    out << text;
    out.close();
    if (!out) fail(path, ": writing failed");
  });
}

}  // namespace pmc
