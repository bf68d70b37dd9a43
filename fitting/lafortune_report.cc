// What a Lafortune fit reports about its solution (fitting/lafortune_fit.h):
// lobe entries on a search limit, energy scaling, the first non-finite
// sample.
#include <sstream>
#include <string>
#include <vector>

#include "fitting/energy.h"
#include "fitting/lafortune_fit.h"

namespace clothfit {

std::vector<LafortuneLimit> LafortuneAtSearchLimit(const LafortuneParams& p) {
  std::vector<LafortuneLimit> out;
  for (size_t k = 0; k < p.lobes.size(); ++k) {
    for (int q = 0; q < 4; ++q) {
      const ParamInfo& info = *kLafortuneLobeEntries[q];
      if (info.physical) continue;
      const glm::dvec3& field = p.lobes[k].*kLafortuneLobeFields<double>[q];
      for (int c = 0; c < 3; ++c) {
        if (OnFitBound(field[c], info.fit_lo, info.fit_hi)) {
          out.push_back({"lobes[" + std::to_string(k) + "]." + info.name +
                             ChannelSuffix(c),
                         field[c]});
        }
      }
    }
  }
  return out;
}

void ReportLafortuneLimits(const LafortuneParams& p, FitReport* report) {
  // A lobe entry on a search limit: the solver wanted to leave the range
  // where a lobe means something (the rule of the other fits,
  // fitting/least_squares.cc).
  const std::vector<LafortuneLimit> limits = LafortuneAtSearchLimit(p);
  report->at_search_limit = static_cast<int>(limits.size());
  if (!limits.empty()) {
    report->converged = false;
    std::ostringstream msg;
    msg << limits.front().name << " stopped at its search limit "
        << limits.front().value;
    if (limits.size() > 1) {
      msg << " (and " << limits.size() - 1 << " more lobe entries)";
    }
    msg << ": a lobe collapsed to a constant (N = 0.5) or is narrower than "
           "the data resolve (N = 200); try fewer lobes (--lobes, "
           "--tolerance)";
    report->message = msg.str();
  }
  MarkEnergyScaled(report);
}

// Names the first sample whose model value is not finite: the table line of its
// first row and its directions in the texel's frame.
std::string LafortuneNonFiniteSample(const TexelSamples& s,
                                     const std::vector<glm::dvec3>& t,
                                     const LafortuneParams& p) {
  for (size_t i = 0; i < s.size(); ++i) {
    const glm::dvec3 m = t[s.view[i]] * LafortuneF1(p, s.l[i], s.v[i]);
    if (std::isfinite(glm::dot(m - s.value[i], glm::dvec3(1.0)))) continue;
    std::ostringstream out;
    out.precision(6);
    out << "the model value is (" << m.x << ", " << m.y << ", " << m.z
        << ") at line " << s.source_line[i] << " of the table, light ("
        << s.l[i].x << ", " << s.l[i].y << ", " << s.l[i].z << ") and view ("
        << s.v[i].x << ", " << s.v[i].y << ", " << s.v[i].z
        << ") in the texel's frame";
    return out.str();
  }
  return "non-finite model values";
}

}  // namespace clothfit
