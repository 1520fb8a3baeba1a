// output_guard.h — "no half-written output": files a command promised are
// removed again if the command fails before it completes.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

namespace pmc {

class OutputGuard {
 public:
  void track(const std::string& path) { paths_.push_back(path); }
  void commit() { paths_.clear(); }
  ~OutputGuard() {
    for (const std::string& p : paths_) std::remove(p.c_str());
  }

 private:
  std::vector<std::string> paths_;
};

}  // namespace pmc
