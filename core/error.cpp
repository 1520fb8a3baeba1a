// error.cpp — warnings go to stderr with a common prefix; ConfigError's
// marked setting names (each between two kMark characters).
#include "core/error.h"

#include <cstdio>

namespace pmc {

std::string printable(const std::string& text) {
  std::string out;
  for (unsigned char c : text) {
    if (c >= 0x20 && c != 0x7f) {
      out += char(c);
    } else {
      char hex[5];
      std::snprintf(hex, sizeof(hex), "\\x%02x", c);
      out += hex;
    }
  }
  return out;
}

namespace {

constexpr char kMark = '\x1f';  // ASCII unit separator: never in a file name or a number

std::string render_marked(const std::string& marked, const SettingRename& rename,
                          std::vector<std::string>* names) {
  std::string out;
  for (size_t i = 0; i < marked.size();) {
    const size_t open = marked.find(kMark, i);
    const size_t close = open == std::string::npos ? open : marked.find(kMark, open + 1);
    if (close == std::string::npos) {
      out += marked.substr(i);
      break;
    }
    const std::string name = marked.substr(open + 1, close - open - 1);
    out += marked.substr(i, open - i);
    out += rename ? rename(name) : name;
    if (names) names->push_back(name);
    i = close + 1;
  }
  return out;
}

}  // namespace

std::ostream& operator<<(std::ostream& os, SettingName s) { return os << kMark << s.name << kMark; }

ConfigError::ConfigError(const std::string& marked)
    : Error(render_marked(marked, nullptr, nullptr)), marked_(marked) {}

std::string phrase_settings(const std::string& marked, const SettingRename& rename) {
  return render_marked(marked, rename, nullptr);
}

namespace {
SettingRename& warning_rename() {
  static SettingRename rename;
  return rename;
}
}  // namespace

void set_warning_settings(const SettingRename& rename) { warning_rename() = rename; }

void warn(const std::string& message) {
  std::fprintf(stderr, "pmc: warning: %s\n", phrase_settings(message, warning_rename()).c_str());
}

std::vector<std::string> ConfigError::settings() const {
  std::vector<std::string> names;
  render_marked(marked_, nullptr, &names);
  return names;
}

}  // namespace pmc
