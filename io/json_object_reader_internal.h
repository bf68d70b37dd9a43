// Reading one JSON object of a file (a parameter file and its parts) with
// errors that name the file and the key. Internal to clothfit_io.
#pragma once

#include <cmath>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "io/input_error.h"

namespace clothfit {
namespace io_internal {

// Ordered, so that a "fit" object keeps its key order through a rewrite.
using json = nlohmann::ordered_json;

// Walks one JSON object: typed getters that name the key on error, and a
// final check that no unknown key was left.
class ObjectReader {
 public:
  ObjectReader(const json& object, std::string file, std::string path)
      : object_(object), file_(std::move(file)), path_(std::move(path)) {
    if (!object_.is_object())
      Fail(path_.empty() ? "(top level)" : path_, "must be a JSON object");
  }

  [[noreturn]] void Fail(const std::string& key,
                         const std::string& problem) const {
    throw InputError(file_ + ": key '" + key + "': " + problem);
  }

  std::string Path(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
  }

  bool Has(const std::string& key) const { return object_.contains(key); }

  const json& Get(const std::string& key) {
    if (!object_.contains(key)) Fail(Path(key), "missing");
    used_.insert(key);
    return object_.at(key);
  }

  double Number(const std::string& key) {
    const json& v = Get(key);
    if (!v.is_number()) Fail(Path(key), "must be a number");
    const double x = v.get<double>();
    if (!std::isfinite(x)) Fail(Path(key), "must be finite");
    return x;
  }

  double NumberOr(const std::string& key, double fallback) {
    return Has(key) ? Number(key) : fallback;
  }

  std::string String(const std::string& key) {
    const json& v = Get(key);
    if (!v.is_string()) Fail(Path(key), "must be a string");
    return v.get<std::string>();
  }

  std::vector<double> NumberArray(const std::string& key) {
    const json& v = Get(key);
    if (!v.is_array()) Fail(Path(key), "must be an array of numbers");
    std::vector<double> out;
    for (size_t i = 0; i < v.size(); ++i) {
      const std::string where = Path(key) + "[" + std::to_string(i) + "]";
      if (!v[i].is_number()) Fail(where, "must be a number");
      out.push_back(v[i].get<double>());
      if (!std::isfinite(out.back())) Fail(where, "must be finite");
    }
    return out;
  }

  glm::dvec3 Rgb(const std::string& key) {
    const json& v = Get(key);
    if (v.is_number()) {
      const double x = Number(key);
      return glm::dvec3(x);
    }
    const std::vector<double> a = NumberArray(key);
    if (a.size() != 3) {
      Fail(Path(key),
           "must be a number or an array of 3 numbers (r, g, b), "
           "got " +
               std::to_string(a.size()) + " entries");
    }
    return glm::dvec3(a[0], a[1], a[2]);
  }

  // Throws on any key not read.
  void Finish() const {
    for (auto it = object_.begin(); it != object_.end(); ++it) {
      if (!used_.count(it.key())) Fail(Path(it.key()), "unknown key");
    }
  }

 private:
  const json& object_;
  std::string file_;
  std::string path_;
  std::set<std::string> used_;
};

}  // namespace io_internal
}  // namespace clothfit
