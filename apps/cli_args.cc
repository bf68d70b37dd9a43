#include "apps/cli_args.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "apps/progress.h"
#include "io/atomic_file.h"
#include "io/input_error.h"
#include "io/text_util.h"

namespace clothfit {

CommandArgs::CommandArgs(std::string command, std::string usage,
                         std::string summary)
    : command_(std::move(command)),
      usage_(std::move(usage)),
      summary_(std::move(summary)) {}

void CommandArgs::Option(const std::string& name, const std::string& value_name,
                         const std::string& help, const std::string& fallback) {
  order_.push_back(name);
  specs_[name] = Spec{value_name, help, fallback};
}

void CommandArgs::Flag(const std::string& name, const std::string& help) {
  order_.push_back(name);
  specs_[name] = Spec{"", help, ""};
}

void CommandArgs::Fail(const std::string& message) const {
  throw InputError("clothfit " + command_ + ": " + message +
                   " (see 'clothfit " + command_ + " --help')");
}

bool CommandArgs::Parse(int argc, char** argv, int first) {
  // Every command's: long work draws a progress line on a terminal.
  if (!specs_.count("quiet")) {
    Flag("quiet", "no progress line on the terminal (warnings still shown)");
  }
  for (int i = first; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << Help();
      return false;
    }
    if (arg.rfind("--", 0) != 0 || arg == "--") {
      if (positional_.size() == max_positional_) {
        Fail("unexpected argument '" + arg + "'" +
             (max_positional_ == 0 ? std::string(" (options start with --)")
                                   : std::string()));
      }
      positional_.push_back(arg);
      continue;
    }
    std::string name = arg.substr(2);
    std::string value;
    bool has_inline = false;
    const size_t eq = name.find('=');
    if (eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
      has_inline = true;
    }
    const auto it = specs_.find(name);
    if (it == specs_.end()) {
      Fail("unknown option '--" + text_util::EscapeControl(name) + "'" +
           text_util::DidYouMean(name, order_, "--"));
    }
    if (values_.count(name)) Fail("option '--" + name + "' given twice");
    if (it->second.value_name.empty()) {
      if (has_inline) Fail("option '--" + name + "' takes no value");
      values_[name] = "1";
      continue;
    }
    if (!has_inline) {
      if (i + 1 >= argc) {
        Fail("option '--" + name + "' needs a value (" + it->second.value_name +
             ")");
      }
      value = argv[++i];
    }
    if (value.empty()) {
      Fail("option '--" + name + "' needs a value (" + it->second.value_name +
           "), got ''");
    }
    values_[name] = value;
  }
  CheckFiles();
  progress::SetQuiet(Has("quiet"));
  return true;
}

void CommandArgs::Files(const std::vector<std::string>& inputs,
                        const std::vector<std::string>& outputs) {
  inputs_ = inputs;
  outputs_ = outputs;
}

void CommandArgs::CheckFiles(const NamedFile* derived) const {
  std::vector<NamedFile> inputs, outputs;
  for (const std::string& name : inputs_) {
    if (Has(name)) inputs.push_back({"--" + name, values_.at(name)});
  }
  for (const std::string& name : outputs_) {
    if (Has(name)) outputs.push_back({"--" + name, values_.at(name)});
  }
  if (derived != nullptr) outputs.push_back(*derived);
  // A parameter mip map's index copy is written (and may be read) beside it.
  for (std::vector<NamedFile>* files : {&inputs, &outputs}) {
    for (size_t i = 0, n = files->size(); i < n; ++i) {
      const NamedFile f = (*files)[i];
      // (A device gets the EXR alone.)
      if (text_util::HasExtension(f.path, ".exr") &&
          (files == &inputs || !ResolveOutput(f.path).direct())) {
        files->push_back({"the index copy of " + f.option, f.path + ".json"});
      }
    }
  }
  CheckOutputsDistinct(outputs, inputs);
  // Every output can be written, before anything runs: a failure after the
  // first of several outputs would leave a partial result.
  for (const NamedFile& out : outputs) CheckWritable(out.path);
}

void CommandArgs::CheckDerivedOutput(const std::string& what,
                                     const std::string& path) const {
  const NamedFile derived{what, path};
  CheckFiles(&derived);
}

bool CommandArgs::Has(const std::string& name) const {
  return values_.count(name) > 0;
}

std::string CommandArgs::Get(const std::string& name) const {
  const auto it = values_.find(name);
  if (it != values_.end()) return it->second;
  const auto spec = specs_.find(name);
  if (spec != specs_.end() && !spec->second.fallback.empty()) {
    return spec->second.fallback;
  }
  Fail("option '--" + name + "' is required");
}

std::string CommandArgs::Required(const std::string& name) const {
  if (!Has(name)) Fail("option '--" + name + "' is required");
  return Get(name);
}

double CommandArgs::GetDouble(const std::string& name) const {
  const std::string text = Get(name);
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(x)) {
    Fail("option '--" + name + "': cannot parse '" + text +
         "' as a finite number");
  }
  return x;
}

long CommandArgs::GetInt(const std::string& name) const {
  const std::string text = Get(name);
  char* end = nullptr;
  errno = 0;
  const long x = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE) {
    Fail("option '--" + name + "': cannot parse '" + text + "' as an integer");
  }
  return x;
}

std::string CommandArgs::Help() const {
  std::ostringstream out;
  out << "usage: " << usage_ << "\n\n" << summary_ << "\n\noptions:\n";
  for (const std::string& name : order_) {
    const Spec& s = specs_.at(name);
    std::string left = "  --" + name;
    if (!s.value_name.empty()) left += " " + s.value_name;
    out << left;
    out << std::string(left.size() < 28 ? 28 - left.size() : 1, ' ') << s.help;
    if (!s.fallback.empty()) out << " (default: " << s.fallback << ")";
    out << "\n";
  }
  out << "  --help                    this text\n";
  return out.str();
}

}  // namespace clothfit
