#include "fitting/fit_result.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/input_error.h"
#include "io/text_util.h"

namespace clothfit {

namespace {

std::string SourceOf(const MeasurementTable& table) {
  return table.source.empty() ? std::string("table") : table.source;
}

}  // namespace

void RequireWeightedRows(const MeasurementTable& table) {
  RequireWeightedRows(
      table, std::any_of(table.rows.begin(), table.rows.end(),
                         [](const TableRow& row) { return row.weight > 0.0; }));
}

void RequireWeightedRows(const MeasurementTable& table, bool any_weighted) {
  if (!any_weighted) {
    throw InputError(SourceOf(table) +
                     ": every row has weight 0: nothing to fit");
  }
}

int CountNotReflection(const MeasurementTable& table,
                       const std::string& model) {
  const size_t count = static_cast<size_t>(
      std::count_if(table.rows.begin(), table.rows.end(),
                    [](const TableRow& row) { return !IsReflectionRow(row); }));
  return CountNotReflection(table, count, table.rows.size(), model);
}

int CountNotReflection(const MeasurementTable& table, size_t count, size_t rows,
                       const std::string& model) {
  if (count > 0 && count == rows) {
    throw InputError(
        SourceOf(table) +
        ": no row has both the light and the view above the surface (wi.z "
        "and wo.z > 0); the " +
        model + " model is reflection only");
  }
  return static_cast<int>(count);
}

void ReportWeighting(const Weighting& weighting, FitReport* report) {
  report->noise_model = NoiseKindName(weighting.kind());
  report->noise_level = weighting.level();
  report->noise_level_estimated = !weighting.LevelKnown();
  report->noise_floor = weighting.floor();
  report->minimised =
      weighting.kind() == NoiseKind::kRelative   ? "relative error"
      : weighting.kind() == NoiseKind::kAbsolute ? "error"
                                                 : "error in sigmas";
  report->minimised_rms =
      report->residuals > 0
          ? weighting.WeightLevel() *
                std::sqrt(2.0 * report->final_cost / report->residuals)
          : 0.0;
  if (report->noise_level_estimated) {
    // F^2 = 2 cost / dof: the weights were those of F = 1.
    int free = 0;
    for (const ParameterReport& p : report->parameters) free += p.free ? 1 : 0;
    const int dof = report->residuals - free;
    report->noise_level =
        dof > 0 ? std::sqrt(2.0 * report->final_cost / dof) : 0.0;
  }
}

void ReportChannelsFollowRed(const std::string& name, FitReport* report) {
  // Parameter name without its last two characters ("_r") -> red value.
  std::map<std::string, double> red;
  for (const ParameterReport& p : report->parameters) {
    if (text_util::EndsWith(p.name, name + "_r")) {
      red[p.name.substr(0, p.name.size() - 2)] = p.value;
    }
  }
  for (ParameterReport& p : report->parameters) {
    if (text_util::EndsWith(p.name, name + "_g") ||
        text_util::EndsWith(p.name, name + "_b")) {
      const auto it = red.find(p.name.substr(0, p.name.size() - 2));
      if (it != red.end()) p.value = it->second;
    }
  }
}

glm::dvec3 OneChannelRgb(const std::string& name, const glm::dvec3& rgb,
                         FitReport* report) {
  ReportChannelsFollowRed(name, report);
  return glm::dvec3(rgb.x);
}

std::string FitReportJson(const FitReport& r) {
  nlohmann::ordered_json j;
  j["usable"] = r.usable;
  j["converged"] = r.converged;
  j["termination"] = r.termination;
  j["message"] = r.message;
  j["final_cost"] = r.final_cost;
  j["rms"] = r.rms;
  j["relative_rms"] = r.relative_rms;
  j["iterations"] = r.iterations;
  j["residuals"] = r.residuals;
  j["rows"] = r.rows;
  if (r.rows_not_used > 0) j["rows_not_used"] = r.rows_not_used;
  j["starts"] = r.starts;
  if (!r.search.empty()) j["search"] = r.search;
  if (!r.noise_model.empty()) {
    nlohmann::ordered_json noise;
    noise["model"] = r.noise_model;
    if (r.noise_model != "table") {
      noise["level"] = r.noise_level;
      noise["level_estimated"] = r.noise_level_estimated;
    }
    if (r.noise_model == "relative") {
      noise["floor"] = {r.noise_floor.x, r.noise_floor.y, r.noise_floor.z};
    }
    noise["minimised"] = r.minimised;
    noise["minimised_rms"] = r.minimised_rms;
    j["noise"] = noise;
  }
  if (r.alternations > 0) {
    j["alternations"] = r.alternations;
    j["lut_change"] = r.lut_change;
    j["view_relative_rms"] = r.view_relative_rms;
    j["lut_views"] = r.lut_views;
    j["lut_views_fitted"] = r.lut_views_fitted;
    j["lut_views_at_energy_bound"] = r.lut_views_at_energy_bound;
    if (r.solve_fallback) j["solve_fallback"] = "alternate";
  }
  if (r.max_albedo >= 0.0) {
    nlohmann::ordered_json energy;
    energy["max_albedo"] = r.max_albedo;
    energy["at"] = r.max_albedo_at;
    energy["scaled_by"] = r.energy_scale;
    if (r.max_light_albedo >= 0.0) {
      energy["light_side_max_albedo"] = r.max_light_albedo;
      energy["light_side_at"] = r.max_light_albedo_at;
    }
    if (!r.energy_bound.empty()) energy["bound"] = r.energy_bound;
    j["energy"] = energy;
  }
  nlohmann::ordered_json values = nlohmann::ordered_json::object();
  for (const ParameterReport& p : r.parameters) values[p.name] = p.value;
  j["values"] = values;
  nlohmann::ordered_json stddev = nlohmann::ordered_json::object();
  nlohmann::ordered_json sandwich = nlohmann::ordered_json::object();
  nlohmann::ordered_json fixed = nlohmann::ordered_json::array();
  nlohmann::ordered_json at_bound = nlohmann::ordered_json::array();
  for (const ParameterReport& p : r.parameters) {
    if (!p.free) {
      fixed.push_back(p.name);
      continue;
    }
    if (p.stddev >= 0.0) stddev[p.name] = p.stddev;
    if (p.stddev_sandwich >= 0.0) sandwich[p.name] = p.stddev_sandwich;
    if (p.at_bound) at_bound.push_back(p.name);
  }
  j["stddev"] = stddev;
  if (!sandwich.empty()) j["stddev_sandwich"] = sandwich;
  j["fixed"] = fixed;
  if (!at_bound.empty()) j["at_bound"] = at_bound;
  if (!r.identifiability.empty()) j["identifiability"] = r.identifiability;
  if (r.stddev_conditional) j["stddev_conditional"] = true;
  return j.dump();
}

std::string FitReportText(const FitReport& r,
                          const std::vector<double>& truth) {
  std::ostringstream out;
  char line[256];
  // The fit's verdict, then the solver's own word: a solver that reports
  // CONVERGENCE at a search limit has not given a converged fit.
  std::snprintf(line, sizeof(line),
                "fit: %s; solver: %s, %d iterations over %d start(s), "
                "%.3f s\n",
                r.usable ? (r.converged ? "converged"
                                        : "not converged (the 'reason' "
                                          "line says why)")
                         : "FAILED (the 'reason' line says why)",
                r.termination.c_str(), r.iterations, r.starts, r.seconds);
  out << line;
  std::snprintf(line, sizeof(line),
                "cost %.6g, rms %.4g, relative rms %.4g over %d residuals\n",
                r.final_cost, r.rms, r.relative_rms, r.residuals);
  out << line;
  if (!r.noise_model.empty()) {
    if (r.noise_model == "table") {
      out << "noise: the table's sigma";
    } else {
      std::snprintf(
          line, sizeof(line), "noise: %s, level %.3g%s", r.noise_model.c_str(),
          r.noise_level,
          r.noise_level_estimated ? " (estimated from the residuals)" : "");
      out << line;
    }
    std::snprintf(line, sizeof(line), "; minimised: the %s, rms %.4g\n",
                  r.minimised.c_str(), r.minimised_rms);
    out << line;
  }
  if (!r.search.empty()) out << "starts: " << r.search << "\n";
  if (r.alternations > 1 && r.lut_views > 0) {
    std::snprintf(line, sizeof(line),
                  "%d alternation(s); last mean relative change of the lookup "
                  "table %.3g\n",
                  r.alternations, r.lut_change);
    out << line;
  } else if (r.alternations == 1 && r.lut_views_fitted > 0) {
    out << "1 alternation (the lookup table's change is measured from the "
           "second on)\n";
  }
  if (r.alternations > 0) {
    if (r.lut_views_fitted < r.lut_views) {
      std::snprintf(line, sizeof(line),
                    "lookup table: %d of %d views have enough samples for an "
                    "entry of their own; the others take T interpolated from "
                    "them%s\n",
                    r.lut_views_fitted, r.lut_views,
                    r.lut_views_fitted == 0 ? " (none: T = 1)" : "");
      out << line;
    }
    if (r.lut_views_at_energy_bound > 0) {
      std::snprintf(line, sizeof(line),
                    "lookup table: T of %d view(s) lowered to the energy bound "
                    "(the texel would reflect more than it receives there)\n",
                    r.lut_views_at_energy_bound);
      out << line;
    }
  }
  if (r.max_albedo >= 0.0) {
    out << "energy: largest " << r.max_albedo_at;
    if (r.energy_scale < 1.0) {
      std::snprintf(line, sizeof(line), "; scaled by %.4g to conserve energy",
                    r.energy_scale);
      out << line;
    } else if (r.max_albedo > 1.0) {
      out << ": above 1, the model does not conserve energy there";
    }
    out << "\n";
    if (r.max_light_albedo >= 0.0) {
      // Not reciprocal: what a surface lit from wi reflects over all views.
      out << "energy, light side: largest " << r.max_light_albedo_at;
      if (r.max_light_albedo > 1.0) {
        out << ": above 1, the paper's model reflects more than it receives "
               "under light from there (--energy-bound bounds both sides)";
      }
      out << "\n";
    }
    if (!r.energy_bound.empty())
      out << "energy bound: " << r.energy_bound << "\n";
  }
  if (r.rows_not_used > 0) {
    std::snprintf(line, sizeof(line),
                  "%d table row(s) not used (the model cannot explain them)\n",
                  r.rows_not_used);
    out << line;
  }
  std::snprintf(line, sizeof(line), "%-28s %14s %12s%s\n", "parameter", "value",
                "stddev", truth.empty() ? "" : "           true");
  out << line;
  for (size_t i = 0; i < r.parameters.size(); ++i) {
    const ParameterReport& p = r.parameters[i];
    char sd[32];
    if (!p.free) {
      std::snprintf(sd, sizeof(sd), "fixed");
    } else if (p.stddev >= 0.0) {
      std::snprintf(sd, sizeof(sd), "%.3g", p.stddev);
    } else {
      std::snprintf(sd, sizeof(sd), "n/a");
    }
    std::snprintf(line, sizeof(line), "%-28s %14.6g %12s", p.name.c_str(),
                  p.value, sd);
    out << line;
    if (i < truth.size()) {
      std::snprintf(line, sizeof(line), " %14.6g", truth[i]);
      out << line;
    }
    if (p.at_search_limit) {
      out << "  (at search limit)";
    } else if (p.at_bound) {
      out << "  (at bound)";
    }
    if (p.no_effect) out << "  (no effect)";
    out << "\n";
  }
  if (!r.identifiability.empty()) out << r.identifiability << "\n";
  if (r.stddev_conditional) {
    out << "the other standard deviations hold these at their values\n";
  }
  if (!r.usable || !r.converged) out << "reason: " << r.message << "\n";
  return out.str();
}

}  // namespace clothfit
