// Spatially varying Lafortune fits and mip-level group fits (Daubert et
// al. 2001, Section 5.1): every texel of a table with s,t columns is fitted
// on its own; level l+1 pools the samples of each 2 x 2 group of level-l
// texels and fits again, down to 1 x 1, so the work per level stays
// constant. Texels are fitted in parallel on a pool of threads; the results
// do not depend on the number of threads.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "fitting/lafortune_fit.h"
#include "io/param_mipmap.h"

namespace clothfit {

struct LafortuneMipOptions {
  LafortuneFitOptions fit;
  bool mip = true;  // all levels down to 1 x 1; false: level 0 only
  int threads = 0;  // 0: std::thread::hardware_concurrency()
  // > 0: per texel, the smallest lobe count K in 0..3 whose relative RMS
  // error is at most this (else the K with the lowest error).
  double tolerance = 0.0;
  // Told (texels done, texels in all) as fits finish; called from one
  // thread at a time.
  std::function<void(int, int)> progress;
};

struct TexelFit {
  LafortuneModel model;
  int lobes = 0;
  int samples = 0;   // table rows of the texel
  double rms = 0.0;  // over those rows (as rho)
  double relative_rms = 0.0;
  double view_relative_rms = 0.0;  // of the per-view colour (LafortuneErrors)
  bool usable = false;
  std::string message;  // why not usable
  int alternations = 0, iterations = 0;
  double lut_change = 0.0;
  double final_cost = 0.0;  // as LafortuneFitResult's
  bool converged = false;   // as LafortuneFitResult's
  std::string termination;
};

struct LafortuneLevel {
  int width = 0, height = 0;
  std::vector<TexelFit> texels;  // y * width + x
  size_t samples = 0;            // all samples of the level
  double seconds = 0.0;          // wall time of the level's fits
};

struct LafortuneMipResult {
  std::vector<glm::dvec3> views;  // the lookup tables' views (all texels)
  std::vector<LafortuneLevel> levels;
  int fits = 0;
  double seconds = 0.0;
};

// One texel (or a whole table): the fit of the given rows with
// options.fit, or with options.tolerance > 0 the smallest K in 0..3 whose
// relative RMS over the rows is at most the tolerance (else the best K).
TexelFit FitTexelRows(const MeasurementTable& table, const ViewIndex& views,
                      const std::vector<size_t>& rows,
                      const LafortuneMipOptions& options);

// Throws InputError for a table without s,t columns or a transmittance
// table. Level 0 is (max s + 1) x (max t + 1); a level of odd size pools
// its last row/column into the group before (ROUND_DOWN, as OpenEXR).
LafortuneMipResult FitLafortuneMip(const MeasurementTable& table,
                                   const LafortuneMipOptions& options);

// The result as named channels per level (io/param_mipmap.h): "lobes",
// "relative_rms", "diffuse.R/G/B", "lobe{k}.{Cx,Cy,Cz,N}.{R,G,B}" for the
// largest K, and "lut.{v}.{R,G,B,A}" per view; metadata: the views and
// units. Texels with fewer lobes have zeros in the others.
ParamMipmap ToParamMipmap(const LafortuneMipResult& result);

// Texel (x, y) of `level` read back from a mip map written by
// ToParamMipmap (its metadata holds the views).
LafortuneModel TexelFromParamMipmap(const ParamMipmap& mipmap, int level, int x,
                                    int y);
// Every texel of `level` (y * width + x), reading the index once: what a
// renderer loads (api/material.h).
std::vector<LafortuneModel> LevelFromParamMipmap(const ParamMipmap& mipmap,
                                                 int level);

}  // namespace clothfit
