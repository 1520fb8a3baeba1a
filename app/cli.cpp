// cli.cpp — help layout, value checks, three-number options, lists, flag names.
#include "app/cli.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "core/error.h"

namespace pmc::cli {

// ---- help -------------------------------------------------------------------

std::string HelpFormatter::make_usage(const CLI::App* app, std::string name) const {
  auto it = usage_.find(app);
  return "usage: " + (it != usage_.end() ? it->second.first : name + " [options]") + "\n";
}

std::string HelpFormatter::make_description(const CLI::App* app) const {
  auto it = usage_.find(app);
  const std::string& d =
      it != usage_.end() && !it->second.second.empty() ? it->second.second : app->get_description();
  return d.empty() ? "" : "\n" + d + "\n";
}

std::string HelpFormatter::make_help(const CLI::App* app, std::string name, CLI::AppFormatMode) const {
  std::ostringstream out;
  out << make_usage(app, name) << make_description(app);
  // Options by group, in the order the groups were first used; positionals
  // are in the usage line.
  for (const std::string& group : app->get_groups()) {
    if (group.empty()) continue;
    const std::vector<const CLI::Option*> opts =
        app->get_options([&](const CLI::Option* o) { return o->get_group() == group && o->nonpositional(); });
    if (opts.empty()) continue;
    out << "\n" << group << ":\n";
    for (const CLI::Option* o : opts) out << make_option(o, false);
  }
  const std::vector<const CLI::App*> subs =
      app->get_subcommands([](const CLI::App* s) { return !s->get_group().empty(); });
  if (!subs.empty()) {
    out << "\ncommands:\n";
    for (const CLI::App* s : subs)
      CLI::detail::format_help(out, s->get_name(), s->get_description(), column_width_);
  }
  out << make_footer(app);
  return out.str();
}

std::string HelpFormatter::make_option_name(const CLI::Option* opt, bool positional) const {
  if (positional) return opt->get_name(true, false);
  const std::string value = opt->get_items_expected_max() > 0 ? " " + opt->get_type_name() : "";
  std::string names;
  for (const std::string& s : opt->get_snames()) names += (names.empty() ? "-" : ", -") + s + value;
  for (const std::string& l : opt->get_lnames()) names += (names.empty() ? "--" : ", --") + l + value;
  return names;
}

std::string HelpFormatter::make_option_desc(const CLI::Option* opt) const {
  std::string d = opt->get_description();
  if (!opt->get_default_str().empty()) d += " (default: " + opt->get_default_str() + ")";
  return d;
}

HelpFormatter& formatter(CLI::App& app) {
  auto f = std::dynamic_pointer_cast<HelpFormatter>(app.get_formatter());
  PMC_CHECK(f != nullptr, "pmc's help formatter is not set");
  return *f;
}

// ---- values -----------------------------------------------------------------

std::string integer_problem(const std::string& text, long long lo, long long hi) {
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE) return "'" + text + "' is not an integer";
  if (v < lo || v > hi) return text + " is out of range";
  return "";
}

std::string number_problem(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v)) return "'" + text + "' is not a finite number";
  return "";
}

CLI::Validator number() {
  return CLI::Validator([](std::string& s) { return number_problem(s); }, "");
}

CLI::Validator one_of(const std::vector<std::string>& words) {
  return CLI::Validator(
      [words](std::string& s) -> std::string {
        for (const std::string& w : words)
          if (s == w) return "";
        std::string list;
        for (size_t i = 0; i < words.size(); ++i)
          list += (i == 0 ? "" : i + 1 == words.size() ? " or " : ", ") + words[i];
        return "expected " + list + ", got '" + s + "'";
      },
      "");
}

CLI::Validator at_least(long long min) {
  return CLI::Validator(
      [min](std::string& s) -> std::string {
        if (std::string p = integer_problem(s, std::numeric_limits<long long>::min(),
                                            std::numeric_limits<long long>::max());
            !p.empty())
          return p;
        return std::strtoll(s.c_str(), nullptr, 10) < min
                   ? "must be at least " + std::to_string(min) + ", got " + s
                   : "";
      },
      "");
}

CLI::Validator positive() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        if (std::string p = number_problem(s); !p.empty()) return p;
        return std::strtod(s.c_str(), nullptr) > 0.0 ? "" : "must be positive, got " + s;
      },
      "");
}

std::vector<std::string> split_list(const std::string& option, const std::string& text,
                                    const std::string& example) {
  std::vector<std::string> out;
  bool bad = text.empty() || text.back() == ',';
  std::stringstream ss(text);
  std::string item;
  while (!bad && std::getline(ss, item, ',')) {
    const size_t b = item.find_first_not_of(" \t"), e = item.find_last_not_of(" \t");
    if (b == std::string::npos)
      bad = true;
    else
      out.push_back(item.substr(b, e - b + 1));
  }
  if (bad) fail(option, ": '", text, "' is not a comma-separated list (e.g. ", example, ")");
  return out;
}

Vec3 parse_vec3(const std::string& option, const std::string& text) {
  Vec3 v{};
  std::vector<std::string> items;
  try {
    items = split_list(option, text, "1,2,3");
  } catch (const Error&) {
  }
  if (items.size() != 3) fail(option, ": '", text, "' is not three numbers x,y,z");
  for (size_t i = 0; i < 3; ++i) {
    if (!number_problem(items[i]).empty()) fail(option, ": '", text, "' is not three numbers x,y,z");
    v[i] = std::strtof(items[i].c_str(), nullptr);
    if (!std::isfinite(v[i])) fail(option, ": '", text, "' is not three numbers x,y,z");
  }
  return v;
}

CLI::Option* add_vec3(CLI::App& app, const std::string& name, std::function<void(Vec3)> set,
                      const std::string& help) {
  return app
      .add_option_function<std::string>(
          name, [name, set](const std::string& text) { set(parse_vec3(name, text)); }, help)
      ->type_name("x,y,z");
}

std::string parse_error_message(const CLI::ParseError& e) {
  std::string m = e.what();
  if (dynamic_cast<const CLI::ArgumentMismatch*>(&e))
    if (size_t at = m.find(": At Most 1 required but received"); at != std::string::npos)
      return m.substr(0, at) + ": given more than once (it takes one value)";
  return m;
}

// ---- settings and flags -----------------------------------------------------

namespace {
std::map<std::string, std::string>& flags() {
  static std::map<std::string, std::string> map;
  return map;
}
}  // namespace

void name_setting(const std::string& setting, const std::string& flag) { flags()[setting] = flag; }

std::string flag_name(const std::string& setting) {
  if (auto it = flags().find(setting); it != flags().end()) return it->second;
  std::string flag = "--" + setting;
  for (char& c : flag)
    if (c == '_') c = '-';
  return flag;
}

std::string with_flags(const std::string& marked) { return phrase_settings(marked, flag_name); }

}  // namespace pmc::cli
