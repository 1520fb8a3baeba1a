// cli_args.h — a strict, small command-line reader for the pmc subcommands.
//
// Options are declared with their help text; parsing rejects unknown options,
// missing values and malformed numbers with a message naming the option
// (pmc::Error, exit code 2). The same declarations print --help, so the help
// text cannot drift from what is accepted.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace pmc {

class ArgParser {
 public:
  ArgParser(std::string usage, std::string summary)
      : usage_(std::move(usage)), summary_(std::move(summary)) {}
  // An option taking a value; `repeatable` options may appear several times.
  void option(const std::string& name, const std::string& value_name, const std::string& help,
              const std::string& default_text = "", bool repeatable = false);
  void flag(const std::string& name, const std::string& help);
  // A subcommand that gives a shared option another meaning says so here:
  // the option keeps parsing, --help shows the new text. hide() leaves it
  // out of --help (for options the subcommand refuses with its own message).
  void redescribe(const std::string& name, const std::string& value_name, const std::string& help,
                  const std::string& default_text = "");
  void hide(const std::string& name);
  // Returns false if --help was given (help already printed).
  bool parse(const std::vector<std::string>& args);

  bool has(const std::string& name) const { return values_.count(name) > 0; }
  std::string get(const std::string& name, const std::string& fallback = "") const;
  std::vector<std::string> all(const std::string& name) const;
  int get_int(const std::string& name, int fallback) const;
  long long get_int64(const std::string& name, long long fallback) const;
  float get_float(const std::string& name, float fallback) const;
  // "x,y,z" -> three floats.
  bool get_vec3(const std::string& name, float out[3]) const;
  const std::vector<std::string>& positional() const { return positional_; }
  void print_help() const;

 private:
  struct Spec {
    std::string name, value_name, help, default_text;
    bool takes_value = true, repeatable = false, hidden = false;
  };
  std::string usage_, summary_;
  std::vector<Spec> specs_;
  Spec& spec(const std::string& name);
  std::map<std::string, std::vector<std::string>> values_;
  std::vector<std::string> positional_;
};

}  // namespace pmc
