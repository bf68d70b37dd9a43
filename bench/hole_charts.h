// Charts of semi-transparent textures with thickness: the
// transmittance of a mask versus the view angle (Algorithm 3.1, the
// extension, the ground truth), and the error of both methods over hole
// size x thickness for square holes (where each one fails). Each is a PNG
// (charts/chart.h) and the CSV behind it, written atomically.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "holes/hole_texture.h"
#include "io/mask_io.h"

namespace clothfit {

// Transmittance (rho_transparent of the whole tile) at view directions
// theta (degrees from the normal) in one azimuth plane.
struct AngleCurve {
  double thickness_texels = 1.0;
  double azimuth_deg = 0.0;
  int level = 0;                 // level the methods are evaluated at
  int64_t truth_rays = 1000000;  // rays of the ground truth per view
  std::vector<double> theta_deg;
  std::vector<double> alg31, extension, truth;
};

// Evaluates the curve; `texture` must have distances and come from `mask`.
AngleCurve TransmittanceVsAngle(const Mask& mask, const HoleTexture& texture,
                                double thickness_texels, double azimuth_deg,
                                const std::vector<double>& theta_deg, int level,
                                int64_t truth_rays);

// `png` and, beside it, the CSV `csv` (theta_deg, alg31, extension, truth,
// and the errors of both methods).
void WriteAngleChart(const AngleCurve& curve, const std::string& title,
                     const std::string& png, const std::string& csv);

struct ErrorMapOptions {
  // Up to twice the extension's reach (kDistanceBins), where it fails.
  std::vector<int> hole_sizes = {1, 2, 3, 4, 6, 8, 12, 16};
  int bar = 1;  // opaque bar width between the square holes
  std::vector<double> thicknesses = {0.25, 0.5, 1.0, 2.0, 4.0, 8.0};
  std::vector<double> theta_deg = {10, 20, 30, 40, 50, 60, 70, 80};
  std::vector<double> azimuth_deg = {0.0, 22.5, 45.0};
  int truth_samples = 16;
};

// RMS and largest |method - truth| of the whole-tile transmittance over the
// views, per (thickness, hole size): index [t * hole_sizes + s]. The
// methods are evaluated at level 0.
struct ErrorMap {
  ErrorMapOptions options;
  std::vector<double> rms_alg31, rms_extension, max_alg31, max_extension;
};

ErrorMap ComputeErrorMap(const ErrorMapOptions& options);

// Two heat-map panels (Algorithm 3.1 | extension) of the RMS error, and the
// CSV (hole_size, thickness_texels, rms_alg31, rms_extension, max_alg31,
// max_extension).
void WriteErrorMap(const ErrorMap& map, const std::string& png,
                   const std::string& csv);

}  // namespace clothfit
