// Helpers shared by the fuzz targets (fuzz/fuzz_targets.h).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/fuzz_targets.h"
#include "io/table.h"

namespace clothfit::fuzz {

// A private folder for this process's temporary files, created on first
// use and removed at exit.
const std::string& ScratchDir();

// Writes the bytes to `path` (replacing it); aborts the run (a bug in the
// harness, not in the reader) when it cannot.
void WriteBytes(const std::string& path, const uint8_t* data, size_t size);

inline void Require(bool ok, const std::string& what) {
  if (!ok) throw FuzzContractError(what);
}

inline bool Finite(double x) { return std::isfinite(x); }

// Throws FuzzContractError unless the table keeps ReadTable's promises
// (io/table.h): rows, finite numbers, unit directions and normals,
// sigma > 0, weight >= 0, alpha in [0, 1]. (fuzz/table_target.cc)
void CheckTable(const MeasurementTable& table);

}  // namespace clothfit::fuzz
