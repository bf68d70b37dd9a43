// A reflection model or a measured table as the glTF cloth material
// (models/sheen.h), for the glTF export (export/gltf.h): the material that
// fits the source best, and the error that conversion leaves.
#pragma once

#include <string>

#include "fitting/sheen_fit.h"
#include "io/table.h"
#include "models/evaluate.h"

namespace clothfit {

// The directions of the conversion grid: light and view each at polar
// angles 5, 15, ..., 85 degrees and azimuths 0, 30, ..., 330 degrees (108
// directions, 11,664 pairs), the cosine-weighted value rho = f wi.z of
// `model` at every pair (what a renderer integrates; grazing light weighs
// little). Throws InputError for a model that does not reflect (slab
// transmission is left out: the glTF material is opaque; holes).
// `polar` x `azimuth` directions (polar angles (k + 0.5) 90 / polar
// degrees, azimuths every 360 / azimuth degrees) give a coarser grid.
MeasurementTable ReflectionGrid(const ModelParams& model, int polar = 9,
                                int azimuth = 12);

struct SheenConversion {
  SheenParams params;
  FitReport report;
  int rows = 0;
  // RMS(material - source) / RMS(source) over the rows and channels, and
  // the RMS itself, in the table's quantity.
  double relative_rms = 0.0, rms = 0.0;
  std::string quantity;  // the table's quantity name
};

// The material fitted to `table` (a source model's ReflectionGrid, with
// absolute weights: every direction pair counts by its value's size; or a
// measured table, weighted by its own noise model: `noise`).
SheenConversion ConvertToSheen(const MeasurementTable& table,
                               const NoiseModel& noise);

// The squared differences of `sheen` from `source` and the squared values
// of `source` over ReflectionGrid(source, polar, azimuth), added to *diff2
// and *data2 (for a relative RMS over many texels).
void AddGridError(const ModelParams& source, const SheenParams& sheen,
                  int polar, int azimuth, double* diff2, double* data2);

}  // namespace clothfit
