#include "fitting/energy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "models/albedo.h"
#include "models/prepared.h"

namespace clothfit {
namespace {

void Consider(const glm::dvec3& albedo, const glm::dvec3& d, EnergyCheck* e) {
  const double a = std::max({albedo.x, albedo.y, albedo.z});
  // A non-finite albedo is larger than any.
  if (!(a <= e->max_albedo)) {
    e->max_albedo = std::isfinite(a) ? a : HUGE_VAL;
    e->direction = d;
  }
}

}  // namespace

EnergyCheck LafortuneEnergy(const LafortuneModel& m) {
  EnergyCheck out;
  // The bracket's albedo (smooth in the view) on a grid, and at each view
  // whose T is not 1 (there T scales it): a table without a lookup table
  // (T = 1) of a million distinct views costs no more than the grid.
  std::vector<glm::dvec3> dirs = FurnaceDirections(12);
  for (size_t i = 0; i < m.lut.views.size(); ++i) {
    const glm::dvec3& v = m.lut.views[i];
    const double len = glm::length(v);
    const bool scaled =
        i >= m.lut.color.size() || m.lut.color[i] != glm::dvec3(1.0);
    if (len > 0.0 && v.z > 0.0 && scaled) dirs.push_back(v / len);
  }
  const TexelFrame frame = MakeTexelFrame(m.normal);
  std::vector<glm::dvec3> local(dirs.size());
  for (size_t i = 0; i < dirs.size(); ++i) {
    local[i] = ToTexelFrame(frame, dirs[i]);
  }
  const std::vector<glm::dvec3> bracket = LafortuneBracketAlbedos(
      m.params, local,
      std::vector<glm::dvec3>(dirs.size(), glm::dvec3(0.0, 0.0, 1.0)));
  for (size_t i = 0; i < dirs.size(); ++i) {
    Consider(LookupView(m.lut, dirs[i]).color * bracket[i], dirs[i], &out);
  }
  return out;
}

EnergyCheck ModelEnergy(const ModelParams& params) {
  if (const auto* m = std::get_if<LafortuneModel>(&params)) {
    return LafortuneEnergy(*m);
  }
  EnergyCheck out;
  const HemisphereQuadrature q = MakeHemisphereQuadrature(36);
  const auto* t = std::get_if<ThreadParams>(&params);
  const auto* c = std::get_if<ClothParams>(&params);
  const bool both = (t && t->energy_bound) || (c && c->energy_bound);
  for (const glm::dvec3& d : FurnaceDirections(8)) {
    Consider(ModelViewAlbedo(params, d, q), d, &out);
    if (both) Consider(ModelLightAlbedo(params, d, q), d, &out);
  }
  return out;
}

EnergyCheck ModelLightSideEnergy(const ModelParams& params) {
  EnergyCheck out;
  out.max_albedo = -1.0;
  const auto* t = std::get_if<ThreadParams>(&params);
  const auto* c = std::get_if<ClothParams>(&params);
  if (!(t && !t->energy_bound) && !(c && !c->energy_bound)) return out;
  const HemisphereQuadrature q = MakeHemisphereQuadrature(36);
  for (const glm::dvec3& d : FurnaceDirections(8)) {
    Consider(ModelLightAlbedo(params, d, q), d, &out);
  }
  return out;
}

glm::dvec3 ModelLightAlbedo(const ModelParams& params, const glm::dvec3& wi,
                            const HemisphereQuadrature& q) {
  const PreparedModel<double> prepared = PrepareModel<double>(params);
  glm::dvec3 a(0.0);
  for (size_t i = 0; i < q.w.size(); ++i) {
    a += q.weight[i] * q.w[i].z *
         EvaluatePrepared(prepared, wi, q.w[i], Quantity::kBrdf);
  }
  return a;
}

glm::dvec3 ModelViewAlbedo(const ModelParams& params, const glm::dvec3& wo,
                           const HemisphereQuadrature& q) {
  if (const auto* m = std::get_if<LafortuneModel>(&params)) {
    return LafortuneViewAlbedo(*m, wo);
  }
  const PreparedModel<double> prepared = PrepareModel<double>(params);
  auto rho = [&](const glm::dvec3& wi, const glm::dvec3& v) {
    return EvaluatePrepared(prepared, wi, v, Quantity::kCosineWeighted);
  };
  return QuadratureViewAlbedo(rho, wo, q);
}

int BoundLookupTableByEnergy(const LafortuneParams& p, const glm::dvec3& normal,
                             const std::vector<glm::dvec3>& views,
                             std::vector<glm::dvec3>* t) {
  const TexelFrame frame = MakeTexelFrame(normal);
  std::vector<glm::dvec3> local(views.size());
  for (size_t k = 0; k < views.size(); ++k) {
    local[k] = ToTexelFrame(frame, glm::normalize(views[k]));
  }
  const std::vector<glm::dvec3> bracket = LafortuneBracketAlbedos(
      p, local,
      std::vector<glm::dvec3>(views.size(), glm::dvec3(0.0, 0.0, 1.0)));
  int lowered = 0;
  for (size_t k = 0; k < views.size(); ++k) {
    if (!(views[k].z > 0.0)) continue;
    bool low = false;
    for (int c = 0; c < 3; ++c) {
      if ((*t)[k][c] * bracket[k][c] > 1.0) {
        (*t)[k][c] = 1.0 / bracket[k][c];
        low = true;
      }
    }
    lowered += low ? 1 : 0;
  }
  return lowered;
}

namespace {

// The report's fields of the fit's model's checks (ModelEnergy and
// ModelLightSideEnergy); `scale`: the factor that model was then scaled
// by, which scales the light side written too.
void RecordEnergy(const EnergyCheck& e, EnergyCheck light, double scale,
                  FitReport* report) {
  report->max_albedo = e.max_albedo;
  report->max_albedo_at = DescribeEnergy(e);
  if (light.max_albedo >= 0.0) {
    light.max_albedo *= scale;
    report->max_light_albedo = light.max_albedo;
    report->max_light_albedo_at = DescribeEnergy(light);
  }
}

}  // namespace

void ReportModelEnergy(const ModelParams& fitted, FitReport* report) {
  if (report->max_albedo >= 0.0) return;
  RecordEnergy(ModelEnergy(fitted), ModelLightSideEnergy(fitted), 1.0, report);
}

double ConserveEnergyByScale(const ModelParams& fitted,
                             const PredictionPairs& pairs, double* scale,
                             FitReport* report) {
  const EnergyCheck e = ModelEnergy(fitted);
  const bool conserves = !(e.max_albedo > 1.0) || !std::isfinite(e.max_albedo);
  // The model is linear in its factor: what is written has s times the
  // fit's light-side albedo too.
  RecordEnergy(e, ModelLightSideEnergy(fitted),
               conserves ? 1.0 : 1.0 / e.max_albedo, report);
  if (conserves) return 1.0;
  const double s = 1.0 / e.max_albedo;
  *scale *= s;
  report->energy_scale = s;
  // The model is linear in its factor: the scaled model's values are s
  // times the fit's.
  double se = 0.0, ss = 0.0;
  size_t n = 0;
  pairs([&](double model, double measured) {
    const double d = s * model - measured;
    se += d * d;
    ss += measured * measured;
    ++n;
  });
  report->rms = std::sqrt(se / std::max<size_t>(1, n));
  report->relative_rms = ss > 0.0 ? std::sqrt(se / ss) : 0.0;
  for (ParameterReport& p : report->parameters) {
    if (p.name != "scale") continue;  // the fitted factor, as written
    p.value *= s;
    if (p.stddev > 0.0) p.stddev *= s;
    if (p.stddev_sandwich > 0.0) p.stddev_sandwich *= s;
  }
  MarkEnergyScaled(report);
  return s;
}

void MarkEnergyScaled(FitReport* report) {
  if (!(report->energy_scale < 1.0)) return;
  report->converged = false;
  std::ostringstream msg;
  msg.precision(4);
  msg << "the fitted model reflected more than it received, "
      << report->max_albedo_at << "; it was scaled by " << report->energy_scale
      << " to conserve energy (data brighter than a physical surface: "
         "check the table's calibration)";
  if (!report->message.empty()) msg << "; " << report->message;
  report->message = msg.str();
}

void ScaleLafortuneAlbedo(double s, LafortuneParams* p) {
  p->diffuse *= s;
  for (LafortuneLobe& lobe : p->lobes) {
    for (int c = 0; c < 3; ++c) {
      const double f = std::pow(s, 1.0 / lobe.n[c]);
      lobe.cx[c] *= f;
      lobe.cy[c] *= f;
      lobe.cz[c] *= f;
    }
  }
}

std::string DescribeEnergy(const EnergyCheck& e) {
  const double theta =
      std::acos(std::clamp(e.direction.z, -1.0, 1.0)) * 180.0 / kPi;
  double phi = std::atan2(e.direction.y, e.direction.x) * 180.0 / kPi;
  if (phi < 0.0) phi += 360.0;
  if (theta < 1e-6) phi = 0.0;
  char text[128];
  std::snprintf(text, sizeof(text),
                "directional albedo %.4g (at theta %.4g, phi %.4g degrees)",
                e.max_albedo, theta, phi);
  return text;
}

}  // namespace clothfit
