#include <vector>

#include "io/holes_tile_json_internal.h"

namespace clothfit {
namespace io_internal {
namespace {

// Entry `key` of the tile: an array of `texels` arrays of `width` numbers.
template <size_t N>
std::vector<std::array<double, N>> ReadRows(ObjectReader& r,
                                            const std::string& key,
                                            size_t texels) {
  const json& rows = r.Get(key);
  const std::string path = r.Path(key);
  if (!rows.is_array() || rows.size() != texels) {
    r.Fail(path, "must be an array of " + std::to_string(texels) +
                     " arrays (one per texel)");
  }
  std::vector<std::array<double, N>> out(texels);
  for (size_t i = 0; i < texels; ++i) {
    const std::string at = path + "[" + std::to_string(i) + "]";
    const json& row = rows[i];
    if (!row.is_array() || row.size() != N) {
      r.Fail(at, "must be an array of " + std::to_string(N) + " numbers");
    }
    for (size_t k = 0; k < N; ++k) {
      if (!row[k].is_number()) r.Fail(at, "must hold numbers only");
      out[i][k] = row[k].get<double>();
    }
  }
  return out;
}

}  // namespace

HolesTile ReadHolesTile(const json& object, const std::string& file,
                        HoleMethod method) {
  ObjectReader r(object, file, "tile");
  HolesTile tile;
  tile.method = method;
  tile.texels.area = r.Number("area");
  const std::vector<double> texels = r.NumberArray("texels");
  if (texels.empty() || texels.size() > kMaxStoredTileTexels) {
    r.Fail(r.Path("texels"),
           "must hold 1 to " + std::to_string(kMaxStoredTileTexels) +
               " texels, got " + std::to_string(texels.size()));
  }
  const auto counts = ReadRows<kHoleCountChannels>(r, "counts", texels.size());
  for (size_t i = 0; i < texels.size(); ++i) {
    HoleTexel t;
    t.counts = counts[i];
    t.texels = texels[i];
    tile.texels.counts.push_back(t);
  }
  if (r.Has("distances")) {
    for (const auto& row :
         ReadRows<kDistanceChannels>(r, "distances", texels.size())) {
      HoleDistanceTexel d;
      d.cumulative = row;
      tile.texels.distances.push_back(d);
    }
  }
  r.Finish();
  const std::string e = ValidateHolesTile(tile);
  if (!e.empty()) {
    const size_t colon = e.find(": ");
    r.Fail(e.substr(0, colon), e.substr(colon + 2));
  }
  return tile;
}

json FormatHolesTile(const HolesTile& tile) {
  json texels = json::array(), counts = json::array();
  for (const HoleTexel& t : tile.texels.counts) {
    texels.push_back(t.texels);
    counts.push_back(t.counts);
  }
  json out = {
      {"area", tile.texels.area}, {"texels", texels}, {"counts", counts}};
  if (!tile.texels.distances.empty()) {
    json distances = json::array();
    for (const HoleDistanceTexel& d : tile.texels.distances) {
      distances.push_back(d.cumulative);
    }
    out["distances"] = distances;
  }
  return out;
}

}  // namespace io_internal
}  // namespace clothfit
