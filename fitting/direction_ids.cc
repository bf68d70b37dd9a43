#include "fitting/direction_ids.h"

#include <cmath>

namespace clothfit {
namespace {

long long Round(double x) { return std::llround(x * 1e9); }

}  // namespace

// FNV-1a over the key's words, then the finaliser of MurmurHash3's
// 64-bit mix, so that the low bits the table's mask keeps depend on every
// bit of every word (linear probing degrades with clustered slots).
size_t HashDirectionKey(const DirectionKey& k) {
  uint64_t h = 1469598103934665603ULL;
  for (long long v : k) h = (h ^ static_cast<uint64_t>(v)) * 1099511628211ULL;
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdULL;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ULL;
  h ^= h >> 33;
  return static_cast<size_t>(h);
}

DirectionKey DirectionKeyOf(const glm::dvec3& w) {
  return {Round(w.x), Round(w.y), Round(w.z), 0, 0, 0};
}

DirectionKey PairKeyOf(const glm::dvec3& wo, const glm::dvec3& wi) {
  return {Round(wo.x), Round(wo.y), Round(wo.z),
          Round(wi.x), Round(wi.y), Round(wi.z)};
}

}  // namespace clothfit
