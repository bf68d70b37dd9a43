// A small command-line parser for the clothfit subcommands: long options
// with values (--out FILE or --out=FILE), flags, and --help. Unknown
// options, missing values and unparsable numbers are InputErrors that name
// the option (exit status 2).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "io/atomic_file.h"

namespace clothfit {

class CommandArgs {
 public:
  // `usage` is the synopsis line, `summary` one sentence on what it does.
  CommandArgs(std::string command, std::string usage, std::string summary);

  // An option that takes a value; `fallback` is shown in --help ("" = none).
  void Option(const std::string& name, const std::string& value_name,
              const std::string& help, const std::string& fallback = "");
  void Flag(const std::string& name, const std::string& help);
  // How many arguments that are not options the command takes (default 0):
  // any more are bad input, never dropped.
  void Positionals(size_t max) { max_positional_ = max; }
  // The options that name files the command reads and writes: Parse
  // refuses an output that is one of the inputs or another output. The
  // default is clothfit's option names: --data, --dirs, --params, --init,
  // --stack, --mask, --compare, --truth are read; --out, --png, --distances,
  // --chart, --error-map, --csv, --transmittance are written.
  void Files(const std::vector<std::string>& inputs,
             const std::vector<std::string>& outputs);
  // The same check for an output the command derives from its options
  // (render's PNG beside --out, a chart's CSV): `what` names it.
  void CheckDerivedOutput(const std::string& what,
                          const std::string& path) const;

  // Parses argv[first..]. Returns false when --help was given (the help
  // text has been printed to stdout). Throws InputError on bad usage.
  bool Parse(int argc, char** argv, int first);

  bool Has(const std::string& name) const;
  // The option's value, else its fallback; throws if neither exists.
  std::string Get(const std::string& name) const;
  std::string Required(const std::string& name) const;
  double GetDouble(const std::string& name) const;
  long GetInt(const std::string& name) const;
  const std::vector<std::string>& Positional() const { return positional_; }

  std::string Help() const;
  // "clothfit CMD: " + message, thrown as InputError.
  [[noreturn]] void Fail(const std::string& message) const;

 private:
  struct Spec {
    std::string value_name;  // empty for flags
    std::string help;
    std::string fallback;
  };
  std::string command_, usage_, summary_;
  std::vector<std::string> order_;
  std::map<std::string, Spec> specs_;
  std::map<std::string, std::string> values_;
  // Checks the files given, and `derived` (may be null) as an output.
  void CheckFiles(const NamedFile* derived = nullptr) const;

  std::vector<std::string> positional_;
  std::vector<std::string> inputs_ = {"data",  "dirs", "params",  "init",
                                      "stack", "mask", "compare", "truth"};
  std::vector<std::string> outputs_ = {
      "out", "png", "distances", "chart", "error-map", "csv", "transmittance"};
  size_t max_positional_ = 0;
};

}  // namespace clothfit
