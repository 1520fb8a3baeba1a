// error.h — how pmc reports bad input and broken invariants.
//
// Bad input (a malformed file, an impossible setting) throws pmc::Error with a
// message that names the file or setting and what was wrong; the command line
// prints it and exits with code 2 (the files a command had started to write
// are removed by app/output_guard.h's OutputGuard as the error unwinds).
// PMC_CHECK guards cheap invariants in release builds too and throws
// pmc::Error as well, so a broken invariant is a message, not a crash.
//
// Layers below app/ know settings by their RenderConfig names (spp,
// cache_entries), not by command-line flags: they throw ConfigError, whose
// message marks each setting it names (fail_config(setting("spp"), ": must
// be at least 1")). what() shows the plain names; app/ shows the flags.
// Warnings mark settings the same way; warn() shows them through the rename
// that app/ installs (set_warning_settings), by their plain names without one.
#pragma once

#include <functional>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

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

// Text read from a file, fit for a message: control bytes (NUL, ESC, ...)
// written as \xNN, so a name cannot cut or garble the line it is quoted in.
std::string printable(const std::string& text);

// A setting's name inside a ConfigError message (see above).
struct SettingName {
  const char* name;
};
inline SettingName setting(const char* name) { return {name}; }
std::ostream& operator<<(std::ostream& os, SettingName s);
using SettingRename = std::function<std::string(const std::string&)>;
// Text with marked setting names, each replaced by rename(name) (by the
// plain name without `rename`). Messages and reasons kept for later display
// (the cache size's reason) are stored marked and shown through this.
std::string phrase_settings(const std::string& marked, const SettingRename& rename = nullptr);
// How warn() shows the settings marked in a warning (app/: their flags).
// Install it before any thread may warn.
void set_warning_settings(const SettingRename& rename);

class ConfigError : public Error {
 public:
  // `marked`: the message with settings streamed through setting().
  explicit ConfigError(const std::string& marked);
  // The message with each setting's name replaced by rename(name).
  std::string phrased(const SettingRename& rename) const { return phrase_settings(marked_, rename); }
  // The settings the message names, in order.
  std::vector<std::string> settings() const;

 private:
  std::string marked_;
};

template <typename... Parts>
[[noreturn]] __attribute__((noinline, cold)) void fail_config(const Parts&... parts) {
  std::ostringstream os;
  (os << ... << parts);
  throw ConfigError(os.str());
}

}  // namespace pmc

#define PMC_CHECK(cond, ...)                                                                        \
  do {                                                                                              \
    if (!(cond)) ::pmc::fail("internal check failed (" #cond ") at " __FILE__ ": ", ##__VA_ARGS__); \
  } while (0)
