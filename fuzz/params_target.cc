// Fuzz target: parameter files (io/params_json.h).
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "fuzz/fuzz_util.h"
#include "io/input_error.h"
#include "io/params_json.h"
#include "models/evaluate.h"

namespace clothfit {
namespace {

using fuzz::Finite;
using fuzz::Require;

// Same JSON, numbers equal to rounding (a read normalises vectors such as
// the Lafortune "normal", so a second write may differ in the last digit).
bool JsonNear(const nlohmann::json& a, const nlohmann::json& b) {
  if (a.is_number() && b.is_number()) {
    const double x = a.get<double>(), y = b.get<double>();
    return std::abs(x - y) <= 1e-12 * std::max(1.0, std::abs(x));
  }
  if (a.type() != b.type() || a.size() != b.size()) return false;
  if (a.is_object()) {
    for (auto it = a.begin(); it != a.end(); ++it) {
      if (!b.contains(it.key()) || !JsonNear(it.value(), b.at(it.key()))) {
        return false;
      }
    }
    return true;
  }
  if (a.is_array()) {
    for (size_t i = 0; i < a.size(); ++i) {
      if (!JsonNear(a[i], b[i])) return false;
    }
    return true;
  }
  return a == b;
}

// A file that was read must write and read back to the same values (every
// number finite and in range, so FormatParamFile's output is valid input).
void CheckRoundTrip(const ParamFile& file) {
  const std::string text = FormatParamFile(file);
  ParamFile back;
  try {
    back = ParseParamFile(text, "round trip");
  } catch (const InputError& error) {
    throw FuzzContractError(std::string("FormatParamFile output does not "
                                        "read back: ") +
                            error.what());
  }
  Require(JsonNear(nlohmann::json::parse(FormatParamFile(back)),
                   nlohmann::json::parse(text)),
          "round trip keeps the values");
}

// A holes file's numbers are finite and its threshold in range.
void CheckHoles(const ParamFile& file) {
  const HolesModel* model = std::get_if<HolesModel>(&file.params);
  if (model == nullptr) return;
  const HolesParams& p = model->params;
  Require(Finite(p.thickness_texels), "finite thickness");
  Require(Finite(p.wall_color.x) && Finite(p.wall_color.y) &&
              Finite(p.wall_color.z),
          "finite wall colour");
  Require(file.holes.threshold > 0.0 && file.holes.threshold <= 1.0,
          "threshold in (0, 1]");
}

// A model that was read is finite everywhere on the hemisphere, grazing
// included (its ranges promise it; writers refuse anything else): light and
// view on a grid of polar angles up to 89.99 degrees and azimuths, in both
// quantities a reflectance file is evaluated in.
void CheckFiniteEverywhere(const ParamFile& file) {
  if (std::holds_alternative<HolesModel>(file.params)) return;  // no mask
  const double thetas[] = {0.0, 0.3, 0.9, 1.3, 1.55, 1.5706};
  const double phis[] = {0.0, 1.0, 2.5, 3.14159, 4.4};
  for (const double ti : thetas) {
    for (const double to : thetas) {
      for (const double po : phis) {
        const glm::dvec3 wi(std::sin(ti), 0.0, std::cos(ti));
        const glm::dvec3 wo(std::sin(to) * std::cos(po),
                            std::sin(to) * std::sin(po), std::cos(to));
        for (const Quantity q : {Quantity::kBrdf, Quantity::kTransmittance}) {
          const glm::dvec3 f = Evaluate(file.params, wi, wo, q);
          Require(Finite(f.x) && Finite(f.y) && Finite(f.z),
                  "the model is finite on the hemisphere");
        }
      }
    }
  }
}

}  // namespace

void FuzzParams(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const ParamFile file = ParseParamFile(text, "fuzz.json");
    CheckHoles(file);
    CheckFiniteEverywhere(file);
    CheckRoundTrip(file);
  } catch (const InputError&) {
    // the expected answer to bad input
  }
}

}  // namespace clothfit
