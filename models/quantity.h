// What a table value or a model output measures (docs/formats.md-2).
#pragma once

namespace clothfit {

enum class Quantity {
  kBrdf,            // f(wi, wo), 1/sr
  kCosineWeighted,  // rho = f |wi.z|
  kTransmittance,   // fraction of light passing straight through (0..1)
};

}  // namespace clothfit
