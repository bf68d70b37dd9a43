// Which entries of a least-squares problem are free: --fix, --free and
// --also-free by name (fitting/least_squares.h ApplyFreeFix, FreeAlso).
#include <string>
#include <vector>

#include "fitting/least_squares.h"
#include "io/input_error.h"

namespace clothfit {
namespace {

bool NameMatches(const std::string& pattern, const std::string& name) {
  if (pattern == name) return true;
  const size_t dot = name.rfind('.');
  const std::string last =
      dot == std::string::npos ? name : name.substr(dot + 1);
  if (pattern == last) return true;
  // "albedo" (or "threads[0].albedo") stands for the three channels.
  for (const char* channel : {"_r", "_g", "_b"}) {
    if (pattern + channel == name || pattern + channel == last) return true;
  }
  // "offsets_deg" (or "threads[0].offsets_deg") for each of an array's
  // entries "offsets_deg[k]".
  const size_t bracket = name.rfind('[');
  if (bracket != std::string::npos && name.back() == ']' &&
      (dot == std::string::npos || bracket > dot)) {
    const std::string array = name.substr(0, bracket);
    const std::string array_last = last.substr(0, last.rfind('['));
    if (pattern == array || pattern == array_last) return true;
  }
  return false;
}

// Sets `free` on the entries each pattern matches; throws for a pattern
// matching nothing.
void Mark(const std::vector<std::string>& patterns, const char* option,
          bool free, std::vector<ParameterSpec>* specs) {
  for (const std::string& pattern : patterns) {
    bool any = false;
    for (ParameterSpec& spec : *specs) {
      if (NameMatches(pattern, spec.name)) {
        spec.free = free;
        any = true;
      }
    }
    if (!any) {
      std::string known;
      for (const ParameterSpec& spec : *specs) known += " " + spec.name;
      throw InputError(std::string(option) + ": unknown parameter '" + pattern +
                       "' (known:" + known + ")");
    }
  }
}

}  // namespace

void ApplyFreeFix(const std::vector<std::string>& fix,
                  const std::vector<std::string>& free_only,
                  std::vector<ParameterSpec>* specs) {
  if (!free_only.empty()) {
    for (ParameterSpec& spec : *specs) spec.free = false;
    Mark(free_only, "--free", true, specs);
  }
  // --free albedo --fix albedo_r frees green and blue; a name in both lists
  // is a contradiction.
  for (const std::string& f : fix) {
    for (const std::string& g : free_only) {
      if (f == g) {
        throw InputError("--fix and --free both name '" + f +
                         "': a parameter is either fixed or free");
      }
    }
  }
  Mark(fix, "--fix", false, specs);
  if (fix.empty() && free_only.empty()) return;
  for (const ParameterSpec& spec : *specs) {
    if (spec.free) return;
  }
  throw InputError("--fix and --free leave no parameter free: nothing to fit");
}

void FreeAlso(const std::vector<std::string>& names,
              std::vector<ParameterSpec>* specs) {
  Mark(names, "--also-free", true, specs);
}

}  // namespace clothfit
