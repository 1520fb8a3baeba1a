// error.h — how pmc reports bad input and broken invariants.
//
// Bad input (a malformed file, an impossible option) throws pmc::Error with a
// message that names the file or option and what was wrong; `main` catches it,
// prints it, removes half-written outputs and exits with code 2. PMC_CHECK
// guards cheap invariants in release builds too and throws pmc::Error as well,
// so a broken invariant is a message, not a crash.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace pmc {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

// Builds a message from streamable parts: fail("file.obj: line ", 3, ": bad index").
template <typename... Parts>
[[noreturn]] __attribute__((noinline, cold)) void fail(const Parts&... parts) {
  std::ostringstream os;
  (os << ... << parts);
  throw Error(os.str());
}

void warn(const std::string& message);

}  // namespace pmc

#define PMC_CHECK(cond, ...)                                                                        \
  do {                                                                                              \
    if (!(cond)) ::pmc::fail("internal check failed (" #cond ") at " __FILE__ ": ", ##__VA_ARGS__); \
  } while (0)
