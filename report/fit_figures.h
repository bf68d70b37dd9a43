// The figures of a model against a measurement table (`clothfit plot`,
// `clothfit report`): what each shows is in docs/plots.md. The data
// functions (CompareRows, PolarPanels, ...) compute what a figure draws;
// WriteFitFigures draws the chosen figures as PNG (charts/).
//
// Geometry: wi (to the light) and wo (to the viewer) are unit vectors in
// the surface frame (normal +z, warp +x). The phase angle is the angle
// between wi and wo. theta_h, theta_d and phi_d are Rusinkiewicz's
// half/difference angles (S. Rusinkiewicz, "A New Change of Variables for
// Efficient BRDF Representation", EGWR 1998, Section 3): h = (wi + wo) /
// |wi + wo| at polar angle theta_h and azimuth phi_h, and wi expressed in
// the frame that takes h to +z (rotations by -phi_h about z, then by
// -theta_h about y) at polar angle theta_d and azimuth phi_d.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "charts/chart.h"
#include "charts/image_chart.h"
#include "io/table.h"
#include "models/evaluate.h"

namespace clothfit {

// The figures, in the order they are drawn; the first three need a table.
inline const std::vector<std::string> kFigureNames = {
    "scatter", "residuals", "polar", "halfdiff", "sphere", "albedo"};
bool FigureNeedsData(const std::string& name);

struct PlotOptions {
  std::vector<double> incidence_deg = {0, 30, 60};
  double phi_deg = 0.0;     // azimuth of the polar plots' plane
  double window_deg = 5.0;  // how far a row may lie from a polar panel
  int sphere_pixels = 256;
};

// Geometry.
double PhaseAngle(const glm::dvec3& wi, const glm::dvec3& wo);  // radians
struct HalfDiff {
  double theta_h = 0.0, phi_h = 0.0, theta_d = 0.0, phi_d = 0.0;  // radians
};
HalfDiff ToHalfDiff(const glm::dvec3& wi, const glm::dvec3& wo);
// The inverse: {wi, wo}.
std::pair<glm::dvec3, glm::dvec3> FromHalfDiff(const HalfDiff& angles);

// Every row of the table: its measured value and the model's (the mean of
// r, g, b, in the table's quantity) and its angles in degrees.
struct RowComparison {
  std::vector<double> measured, model;
  std::vector<double> theta_i_deg, theta_o_deg, phase_deg;
};
RowComparison CompareRows(const ModelParams& model,
                          const MeasurementTable& table);

// One polar panel per incidence: the model's curve in the plane of
// incidence at azimuth phi, and the rows whose wi lies within the window
// of the panel's light and whose wo (above the surface) lies within the
// window of the plane; the title says "N of M rows". `shown` (may be
// null): how many distinct rows the panels show together.
std::vector<PolarPanel> PolarPanels(const ModelParams& model,
                                    const MeasurementTable& table,
                                    const PlotOptions& options,
                                    size_t* shown = nullptr);

// The model (mean of r, g, b, as `quantity`) over theta_h (columns) and
// theta_d (rows) in [0, 90) degrees, at phi_d = 90 and phi_h = 0 degrees;
// grey where wi or wo is below the surface.
ImageChart HalfDiffChart(const ModelParams& model, Quantity quantity,
                         int cells = 90);

// a(theta_o) (fitting/energy.h ModelViewAlbedo, mean of r, g, b) every 3
// degrees at phi_o = 0, 45 and 90 degrees.
ScatterChart AlbedoChart(const ModelParams& model);

// The lit sphere (render/sphere.h RenderSphere, 1 sphere_pixels^2):
// the light at theta 45, phi 135 degrees (kSphereLight), the
// exposure that maps the 99th percentile to white (render/preview.h
// AutoExposure), sRGB. `exposure` (may be null): that exposure.
inline const glm::dvec3 kSphereLight(-0.5, 0.5, 0.70710678118654752);
inline constexpr Rgb8 kSphereBackground = {128, 128, 128};
Picture SphereFigure(const ModelParams& model, const std::string& label,
                     int size, double* exposure = nullptr);

struct WrittenFigures {
  std::vector<std::pair<std::string, std::string>> files;  // name, path
  std::vector<std::string> notes;  // "warning: ..." / "note: ..." lines
};

// Draws `names` (kFigureNames; those needing data are skipped with a note
// when `table` is null) for `model` (called `model_label` in titles), each
// to path_of(name). Throws InputError when a file cannot be written.
WrittenFigures WriteFitFigures(
    const ModelParams& model, const std::string& model_label,
    const MeasurementTable* table, const std::vector<std::string>& names,
    const PlotOptions& options,
    const std::function<std::string(const std::string&)>& path_of);

// The single polar figure of `clothfit plot --out P.png`.
WrittenFigures WritePolarFigure(const ModelParams& model,
                                const std::string& model_label,
                                const MeasurementTable& table,
                                const PlotOptions& options,
                                const std::string& path);

}  // namespace clothfit
