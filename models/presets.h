// The fabrics of Sadeghi et al. 2013: scattering parameters from Table 2,
// coverages and tangent offsets from Table 3 (Appendix A). The explicit
// tangent samples are the table's offsets (docs/models.md); the tables' tangent
// curves are kept alongside (ClothThread::curve with samples = 0) so that a
// caller can resample them. Albedo = the table's colour times its factor.
// The first thread listed in the table runs along u (+x), the second along v.
#pragma once

#include <string>
#include <vector>

#include "models/microcylinder_cloth.h"

namespace clothfit {

namespace preset_detail {

inline ThreadParams Thread(double eta, glm::dvec3 colour, double factor,
                           double kd, double gamma_s_deg, double gamma_v_deg) {
  ThreadParams p;
  p.eta = eta;
  p.kd = kd;
  p.gamma_s_deg = gamma_s_deg;
  p.gamma_v_deg = gamma_v_deg;
  p.albedo = colour * factor;
  return p;
}

inline ClothThread Weave(ThreadDirection dir, double coverage,
                         std::vector<double> offsets_deg,
                         std::vector<double> lengths,
                         const ThreadParams& params) {
  ClothThread th;
  th.direction = dir;
  th.coverage = coverage;
  th.offsets_deg = offsets_deg;
  th.curve.offsets_deg = offsets_deg;
  th.curve.lengths = lengths;
  th.curve.samples = 0;
  th.params = params;
  return th;
}

}  // namespace preset_detail

inline const std::vector<std::string>& PresetNames() {
  static const std::vector<std::string> kNames = {
      "linen_plain",
      "silk_crepe_de_chine",
      "polyester_satin_charmeuse",
      "polyester_satin_charmeuse_back",
      "silk_shot",
      "velvet"};
  return kNames;
}

// Returns false (and leaves *out alone) for an unknown name.
inline bool GetPreset(const std::string& name, ClothParams* out) {
  using preset_detail::Thread;
  using preset_detail::Weave;
  constexpr ThreadDirection kU = ThreadDirection::kU;
  constexpr ThreadDirection kV = ThreadDirection::kV;
  ClothParams c;
  if (name == "linen_plain") {
    const ThreadParams both = Thread(1.46, {0.2, 0.8, 1.0}, 0.3, 0.3, 12, 24);
    c.threads = {Weave(kU, 0.33, {-25, 25}, {1}, both),
                 Weave(kV, 0.33, {-25, 25}, {1}, both)};
  } else if (name == "silk_crepe_de_chine") {
    c.threads = {Weave(kU, 0.75, {-35, -35, 35, 35}, {1, 1, 1},
                       Thread(1.345, {1.0, 0.95, 0.05}, 0.12, 0.2, 5, 10)),
                 Weave(kV, 0.25, {0, 0}, {1},
                       Thread(1.345, {1.0, 0.95, 0.05}, 0.16, 0.3, 18, 32))};
  } else if (name == "polyester_satin_charmeuse") {
    c.threads = {Weave(kU, 0.9, {-32, -32, -18, 0, 0, 18, 32, 32},
                       {1.33, 0.66, 2, 2, 2, 0.66, 1.33},
                       Thread(1.539, {1.0, 0.37, 0.3}, 0.035, 0.1, 2.5, 5)),
                 Weave(kV, 0.1, {0, 0}, {1},
                       Thread(1.539, {1.0, 0.37, 0.3}, 0.2, 0.7, 30, 60))};
  } else if (name == "polyester_satin_charmeuse_back") {
    // Table 3 lists six lengths for eight offsets; the curve of Fig. 19(d)
    // is two pieces, so the missing length is the zero-length jump 30 -> -5.
    c.threads = {Weave(kU, 0.67, {-30, -30, 30, 30, -5, -5, 5, 5},
                       {1.33, 1.33, 1.33, 0, 0.67, 0.67, 0.67},
                       Thread(1.539, {1.0, 0.37, 0.3}, 0.035, 0.1, 2.5, 5)),
                 Weave(kV, 0.33, {0, 0}, {3},
                       Thread(1.539, {1.0, 0.37, 0.3}, 0.2, 0.7, 30, 60))};
  } else if (name == "silk_shot") {
    c.threads = {Weave(kU, 0.86, {-25, -25, 25, 25}, {1.33, 2.67, 1.33},
                       Thread(1.345, {0.1, 1.0, 0.4}, 0.2, 0.1, 4, 8)),
                 Weave(kV, 0.14, {0, 0}, {1},
                       Thread(1.345, {1.0, 0.0, 0.1}, 0.6, 0.1, 5, 10))};
  } else if (name == "velvet") {
    const ThreadParams both = Thread(1.46, {0.05, 0.02, 0.0}, 0.3, 0.1, 6, 12);
    c.threads = {Weave(kU, 0.5, {-90, -50}, {1}, both),
                 Weave(kV, 0.5, {-90, -55, 55, 90}, {0.5, 0, 0.5}, both)};
  } else {
    return false;
  }
  *out = c;
  return true;
}

}  // namespace clothfit
