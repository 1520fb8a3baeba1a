// cli_args.cpp — option parsing and help printing.
#include "app/cli_args.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/error.h"

namespace pmc {

void ArgParser::option(const std::string& name, const std::string& value_name, const std::string& help,
                       const std::string& default_text, bool repeatable) {
  specs_.push_back({name, value_name, help, default_text, true, repeatable});
}

void ArgParser::flag(const std::string& name, const std::string& help) {
  specs_.push_back({name, "", help, "", false, false});
}

bool ArgParser::parse(const std::vector<std::string>& args) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--help" || a == "-h") {
      print_help();
      return false;
    }
    if (a.size() > 1 && a[0] == '-' &&
        !(a.size() > 1 && (std::isdigit((unsigned char)a[1]) || a[1] == '.'))) {
      std::string name = a, value;
      bool inline_value = false;
      if (size_t eq = a.find('='); eq != std::string::npos) {
        name = a.substr(0, eq);
        value = a.substr(eq + 1);
        inline_value = true;
      }
      const Spec* spec = nullptr;
      for (const Spec& s : specs_)
        if (s.name == name) spec = &s;
      if (!spec) fail("unknown option '", name, "' (see --help)");
      if (spec->takes_value) {
        if (!inline_value) {
          if (i + 1 >= args.size()) fail("option ", name, " needs a value (", spec->value_name, ")");
          value = args[++i];
        }
        if (!spec->repeatable && values_.count(name)) fail("option ", name, " given twice");
        values_[name].push_back(value);
      } else {
        if (inline_value) fail("option ", name, " takes no value");
        values_[name].push_back("1");
      }
    } else {
      positional_.push_back(a);
    }
  }
  return true;
}

std::string ArgParser::get(const std::string& name, const std::string& fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second.back();
}

std::vector<std::string> ArgParser::all(const std::string& name) const {
  auto it = values_.find(name);
  return it == values_.end() ? std::vector<std::string>{} : it->second;
}

long long ArgParser::get_int64(const std::string& name, long long fallback) const {
  if (!has(name)) return fallback;
  std::string v = get(name);
  errno = 0;
  char* end = nullptr;
  long long x = std::strtoll(v.c_str(), &end, 10);
  if (v.empty() || *end != '\0' || errno == ERANGE) fail("option ", name, ": '", v, "' is not an integer");
  return x;
}

int ArgParser::get_int(const std::string& name, int fallback) const {
  long long x = get_int64(name, fallback);
  if (x < -2147483647LL || x > 2147483647LL) fail("option ", name, ": ", x, " is out of range");
  return int(x);
}

float ArgParser::get_float(const std::string& name, float fallback) const {
  if (!has(name)) return fallback;
  std::string v = get(name);
  char* end = nullptr;
  float x = std::strtof(v.c_str(), &end);
  if (v.empty() || *end != '\0' || !std::isfinite(x))
    fail("option ", name, ": '", v, "' is not a finite number");
  return x;
}

bool ArgParser::get_vec3(const std::string& name, float out[3]) const {
  if (!has(name)) return false;
  std::string v = get(name);
  float x[3];
  const char* p = v.c_str();
  for (int i = 0; i < 3; ++i) {
    char* end = nullptr;
    x[i] = std::strtof(p, &end);
    if (end == p || !std::isfinite(x[i])) fail("option ", name, ": '", v, "' is not three numbers x,y,z");
    p = end;
    if (i < 2) {
      if (*p != ',') fail("option ", name, ": '", v, "' is not three numbers x,y,z");
      ++p;
    }
  }
  if (*p != '\0') fail("option ", name, ": '", v, "' is not three numbers x,y,z");
  for (int i = 0; i < 3; ++i) out[i] = x[i];
  return true;
}

ArgParser::Spec& ArgParser::spec(const std::string& name) {
  for (Spec& s : specs_)
    if (s.name == name) return s;
  fail("internal: no option ", name, " declared");
}

void ArgParser::redescribe(const std::string& name, const std::string& value_name, const std::string& help,
                           const std::string& default_text) {
  Spec& s = spec(name);
  s.value_name = value_name;
  s.help = help;
  s.default_text = default_text;
}

void ArgParser::hide(const std::string& name) { spec(name).hidden = true; }

void ArgParser::print_help() const {
  std::printf("usage: %s\n\n%s\n\noptions:\n", usage_.c_str(), summary_.c_str());
  for (const Spec& s : specs_) {
    if (s.hidden) continue;
    std::string left = s.name + (s.takes_value ? " " + s.value_name : "");
    std::string help = s.help;
    if (!s.default_text.empty()) help += " (default: " + s.default_text + ")";
    std::printf("  %-28s %s\n", left.c_str(), help.c_str());
  }
}

}  // namespace pmc
