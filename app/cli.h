// cli.h — pmc's command line on CLI11: the help layout, strict values, and
// the flag that sets each RenderConfig field.
//
// Every subcommand is a CLI::App whose options bind to the fields they set.
// This file adds what CLI11 2.1 lacks or gets wrong for pmc:
//  * HelpFormatter: "usage: ..." lines, each option's names with its value
//    ("--cells LIST, --cache-cells LIST") and its default and units in the
//    text, so --help lists exactly what is accepted;
//  * value validators with messages that name the option and the value:
//    integers and finite numbers parsed strictly (CLI11 saturates an int64
//    overflow and accepts nan), one_of() for words, at_least()/positive();
//  * three-number options ("x,y,z") and comma-separated lists, split here
//    because CLI11's delimiter drops empty items ("1,,2" would pass as 1,2);
//  * flag names for settings: options that set a RenderConfig field record
//    it (name_setting) so that a ConfigError from below app/ is shown with
//    the flag (with_flags).
#pragma once

#include <CLI/CLI.hpp>
#include <map>
#include <string>
#include <vector>

#include "gpu/render_config.h"

namespace pmc::cli {

class HelpFormatter : public CLI::Formatter {
 public:
  HelpFormatter() { column_width(32); }
  // The usage line of a (sub)command, without "usage: ", and what it does
  // (printed below it; the command's one-line description is for lists).
  void usage(const CLI::App* app, std::string usage, std::string about = "") {
    usage_[app] = {std::move(usage), std::move(about)};
  }
  std::string make_usage(const CLI::App* app, std::string name) const override;
  std::string make_description(const CLI::App* app) const override;
  std::string make_help(const CLI::App* app, std::string name, CLI::AppFormatMode mode) const override;
  std::string make_option_name(const CLI::Option* opt, bool positional) const override;
  std::string make_option_opts(const CLI::Option*) const override { return ""; }
  std::string make_option_desc(const CLI::Option* opt) const override;

 private:
  std::map<const CLI::App*, std::pair<std::string, std::string>> usage_;
};
// The formatter of `app` (set up by main).
HelpFormatter& formatter(CLI::App& app);

// "" when `text` is a whole number in [lo, hi], else why not.
std::string integer_problem(const std::string& text, long long lo, long long hi);
// "" when `text` is a finite number, else why not.
std::string number_problem(const std::string& text);
template <typename T>
CLI::Validator integer() {
  return CLI::Validator(
      [](std::string& s) {
        return integer_problem(s, std::numeric_limits<T>::min(), std::numeric_limits<T>::max());
      },
      "");
}
CLI::Validator number();
CLI::Validator one_of(const std::vector<std::string>& words);
CLI::Validator at_least(long long min);
CLI::Validator positive();

// "x,y,z": three finite numbers.
Vec3 parse_vec3(const std::string& option, const std::string& text);
// An option taking "x,y,z".
CLI::Option* add_vec3(CLI::App& app, const std::string& name, std::function<void(Vec3)> set,
                      const std::string& help);

// "a,b,c": items without blanks around them; empty items are errors. `option`
// names the option in messages, `example` shows a good list.
std::vector<std::string> split_list(const std::string& option, const std::string& text,
                                    const std::string& example);

// CLI11's message for a parse error, reworded where it is unclear (an
// option given twice: "--spp: At Most 1 required but received 2").
std::string parse_error_message(const CLI::ParseError& e);

// RenderConfig field `setting` is set by `flag`.
void name_setting(const std::string& setting, const std::string& flag);
// The flag of a setting (its RenderConfig name with dashes when none was named).
std::string flag_name(const std::string& setting);
// Text with marked settings (ConfigError messages, the cache size's reason) in flag names.
std::string with_flags(const std::string& marked);

}  // namespace pmc::cli
