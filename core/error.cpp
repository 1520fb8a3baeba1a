// error.cpp — warnings go to stderr with a common prefix.
#include "core/error.h"

#include <cstdio>

namespace pmc {

void warn(const std::string& message) { std::fprintf(stderr, "pmc: warning: %s\n", message.c_str()); }

}  // namespace pmc
