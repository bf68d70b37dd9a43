// The mip levels of a texel map fitted in blocks (clothfit fit --region,
// clothfit merge; docs/scale.md): the levels whose groups span more than
// one block, fitted from their children and from the texture's rows
// streamed from its images, so that no process holds the whole texture.
// Each group's samples and errors are the same sums, in the same order,
// as FitLafortuneMip's over a table of every row: the levels equal a
// single-process fit's bit for bit.
#pragma once

#include <cstddef>
#include <functional>

#include "fitting/lafortune_mip.h"

namespace clothfit {

// Calls `row(image, r)` for every row of a texture (s, t of the whole
// texture) in the order of the table ReadImageStack makes: image by image
// (the index of `directions` below), row by row.
using LafortuneRowStream = std::function<void(
    const std::function<void(size_t image, const TableRow& row)>& row)>;

// Fits levels first_level.. of a width x height texture (with
// options.mip: down to 1 x 1; else there are none) into result->levels,
// given levels 0 .. first_level - 1 (the last's models exact: they start
// their groups' fits). `directions` is the texture's table without its
// rows and one row per image with its directions (ImageStackReader); the
// weighting must not depend on the table's values (a default relative
// noise floor does: InputError). Streams the rows once for the samples of
// every level and once more for the errors (with options.tolerance, once
// per level: the errors choose the lobe count a group's parent starts
// from). Sets result->views, levels, fits and seconds (of this call).
void FitLafortuneUpperLevels(const MeasurementTable& directions, int width,
                             int height, const LafortuneRowStream& stream,
                             const LafortuneMipOptions& options,
                             size_t first_level, LafortuneMipResult* result);

// Whether `noise` weighs a row by itself alone (not by the table's median),
// as a texture fitted in blocks needs; false for relative noise without a
// floor.
bool WeightingIsPerRow(const NoiseModel& noise);

}  // namespace clothfit
