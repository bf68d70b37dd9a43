#include "bench/hole_charts.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "charts/chart.h"
#include "charts/heat_map.h"
#include "data_synthetic/holes_truth.h"
#include "io/atomic_file.h"
#include "io/text_util.h"

namespace clothfit {
namespace {

std::string Number(double v) { return text_util::FormatNumber(v, 9); }

glm::dvec3 ViewDirection(double theta_deg, double phi_deg) {
  const double theta = Radians(theta_deg), phi = Radians(phi_deg);
  return glm::dvec3(std::sin(theta) * std::cos(phi),
                    std::sin(theta) * std::sin(phi), std::cos(theta));
}

}  // namespace

AngleCurve TransmittanceVsAngle(const Mask& mask, const HoleTexture& texture,
                                double thickness_texels, double azimuth_deg,
                                const std::vector<double>& theta_deg, int level,
                                int64_t truth_rays) {
  AngleCurve curve;
  curve.thickness_texels = thickness_texels;
  curve.azimuth_deg = azimuth_deg;
  curve.level = level;
  curve.truth_rays = truth_rays;
  const Footprint tile = TileFootprint(mask, truth_rays);
  curve.theta_deg = theta_deg;
  const LevelTexels texels = GatherLevel(texture, level);
  for (double theta : theta_deg) {
    const glm::dvec2 r =
        ViewOffset(thickness_texels, ViewDirection(theta, azimuth_deg));
    curve.alg31.push_back(
        TileRatios(texels, HoleMethod::kAlgorithm31, r).transparent);
    curve.extension.push_back(
        TileRatios(texels, HoleMethod::kExtension, r).transparent);
    curve.truth.push_back(HoleTruth(mask, r, tile).transparent);
  }
  return curve;
}

void WriteAngleChart(const AngleCurve& curve, const std::string& title,
                     const std::string& png, const std::string& csv) {
  std::string text =
      "# transmittance (rho_transparent of the tile) vs view angle\n"
      "# thickness_texels: " +
      Number(curve.thickness_texels) +
      "\n# azimuth_deg: " + Number(curve.azimuth_deg) +
      "\n# level: " + std::to_string(curve.level) +
      "\n# truth_rays_per_view: " + std::to_string(curve.truth_rays) +
      "\ntheta_deg,alg31,extension,truth,error_alg31,error_extension\n";
  for (size_t i = 0; i < curve.theta_deg.size(); ++i) {
    text += Number(curve.theta_deg[i]) + "," + Number(curve.alg31[i]) + "," +
            Number(curve.extension[i]) + "," + Number(curve.truth[i]) + "," +
            Number(curve.alg31[i] - curve.truth[i]) + "," +
            Number(curve.extension[i] - curve.truth[i]) + "\n";
  }
  ScatterChart chart;
  chart.title = title;
  chart.x_label = "view angle theta (degrees from the normal)";
  chart.y_label = "transmittance";
  chart.y_min = 0.0;
  chart.y_max = 1.0;
  auto series = [&](const char* name, const std::vector<double>& y,
                    const Rgb8& colour, bool dashed, bool markers) {
    ScatterSeries s;
    s.name = name;
    for (size_t i = 0; i < curve.theta_deg.size(); ++i) {
      s.points.push_back({curve.theta_deg[i], y[i], "", false});
    }
    s.lines = true;
    s.dashed = dashed;
    s.markers = markers;
    s.colour = colour;
    return s;
  };
  // Drawn in this order: the truth first, so that the extension, which
  // matches it closely, stays visible on top of it (dashes and markers).
  chart.series = {
      series("ground truth", curve.truth, {0, 0, 0}, false, false),
      series("Algorithm 3.1", curve.alg31, {214, 39, 40}, false, false),
      series("extension", curve.extension, {31, 119, 180}, true, true)};
  WriteScatterChartPng(chart, png);
  WriteFileAtomically(csv, text);
}

ErrorMap ComputeErrorMap(const ErrorMapOptions& options) {
  ErrorMap map;
  map.options = options;
  const size_t cells = options.hole_sizes.size() * options.thicknesses.size();
  map.rms_alg31.assign(cells, 0.0);
  map.rms_extension.assign(cells, 0.0);
  map.max_alg31.assign(cells, 0.0);
  map.max_extension.assign(cells, 0.0);
  for (size_t s = 0; s < options.hole_sizes.size(); ++s) {
    const Mask mask = SquareHoleMask(options.hole_sizes[s], options.bar);
    const LevelTexels texels = GatherLevel(AnalyzeMask(mask, true), 0);
    for (size_t t = 0; t < options.thicknesses.size(); ++t) {
      const size_t cell = t * options.hole_sizes.size() + s;
      double se_alg = 0.0, se_ext = 0.0;
      int views = 0;
      for (double theta : options.theta_deg) {
        for (double phi : options.azimuth_deg) {
          const glm::dvec2 r =
              ViewOffset(options.thicknesses[t], ViewDirection(theta, phi));
          const double truth =
              HoleTruthTile(mask, r, options.truth_samples).transparent;
          const double e_alg =
              TileRatios(texels, HoleMethod::kAlgorithm31, r).transparent -
              truth;
          const double e_ext =
              TileRatios(texels, HoleMethod::kExtension, r).transparent - truth;
          se_alg += e_alg * e_alg;
          se_ext += e_ext * e_ext;
          map.max_alg31[cell] = std::max(map.max_alg31[cell], std::abs(e_alg));
          map.max_extension[cell] =
              std::max(map.max_extension[cell], std::abs(e_ext));
          ++views;
        }
      }
      map.rms_alg31[cell] = std::sqrt(se_alg / std::max(1, views));
      map.rms_extension[cell] = std::sqrt(se_ext / std::max(1, views));
    }
  }
  return map;
}

void WriteErrorMap(const ErrorMap& map, const std::string& png,
                   const std::string& csv) {
  const ErrorMapOptions& o = map.options;
  std::string text =
      "# RMS and largest |method - truth| of the tile transmittance over "
      "the views\n# square holes with bars of " +
      std::to_string(o.bar) + " texel(s); theta_deg:";
  for (double t : o.theta_deg) text += " " + Number(t);
  text += "; azimuth_deg:";
  for (double p : o.azimuth_deg) text += " " + Number(p);
  text +=
      "\n# truth_samples_per_texel_side: " + std::to_string(o.truth_samples) +
      "\nhole_size,thickness_texels,rms_alg31,rms_extension,max_alg31,"
      "max_extension\n";
  HeatMap heatmap;
  heatmap.title = "RMS error of the tile transmittance vs ground truth";
  heatmap.x_title = "hole size (texels)";
  heatmap.y_title = "thickness h";
  heatmap.legend = "RMS error";
  for (int s : o.hole_sizes) heatmap.x_labels.push_back(std::to_string(s));
  // The largest thickness on top.
  HeatMapPanel alg{"Algorithm 3.1", {}, {}};
  HeatMapPanel ext{"extension (8-direction runs)", {}, {}};
  for (size_t t = o.thicknesses.size(); t-- > 0;) {
    heatmap.y_labels.push_back(Number(o.thicknesses[t]));
    for (size_t s = 0; s < o.hole_sizes.size(); ++s) {
      alg.values.push_back(map.rms_alg31[t * o.hole_sizes.size() + s]);
      ext.values.push_back(map.rms_extension[t * o.hole_sizes.size() + s]);
    }
  }
  heatmap.panels = {alg, ext};
  for (size_t t = 0; t < o.thicknesses.size(); ++t) {
    for (size_t s = 0; s < o.hole_sizes.size(); ++s) {
      const size_t cell = t * o.hole_sizes.size() + s;
      text += std::to_string(o.hole_sizes[s]) + "," + Number(o.thicknesses[t]) +
              "," + Number(map.rms_alg31[cell]) + "," +
              Number(map.rms_extension[cell]) + "," +
              Number(map.max_alg31[cell]) + "," +
              Number(map.max_extension[cell]) + "\n";
    }
  }
  WriteHeatMapPng(heatmap, png);
  WriteFileAtomically(csv, text);
}

}  // namespace clothfit
