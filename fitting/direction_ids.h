// Telling directions apart, as the Lafortune fits do: views, lights and
// (light, view) pairs whose coordinates agree to 1e-9 are one (a table
// repeats a direction as the same numbers; 1e-9 absorbs the last digits of
// angles converted to vectors). Ids are given in order of first
// appearance, for a table held in memory (ViewIndex, lafortune_samples.h)
// and for rows read one at a time alike.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <stdexcept>
#include <vector>

namespace clothfit {

// Each coordinate in units of 1e-9, rounded: a direction (the last three
// 0) or a pair (the view's, then the light's).
using DirectionKey = std::array<long long, 6>;
DirectionKey DirectionKeyOf(const glm::dvec3& w);
DirectionKey PairKeyOf(const glm::dvec3& wo, const glm::dvec3& wi);

// A hash of a key whose low bits depend on every bit of every word.
size_t HashDirectionKey(const DirectionKey& key);

// Ids 0, 1, ... of keys in order of first appearance, the keys given one at
// a time. An open-addressing table of ids (4 bytes a slot, at most half
// full) that keeps no keys: key_of(id) gives an id's key from wherever the
// caller keeps it (a node-based hash map of the keys took 72 bytes an
// entry, 2.4 GB for a view, light and pair index of 10^7 rows).
class FirstAppearanceIds {
 public:
  // Room for this many ids without growing (before the first id).
  void Reserve(size_t ids) {
    size_t capacity = 16;
    while (capacity < 2 * ids) capacity *= 2;
    if (size_ == 0 && capacity > slots_.size()) slots_.assign(capacity, -1);
  }
  // The id of `key`: that of an earlier equal key, or the next id, and then
  // *added is true and the caller keeps the key so that key_of gives it
  // from the next call on. Throws std::length_error beyond 2^31 - 1 ids.
  template <typename KeyOf>
  int32_t Id(const DirectionKey& key, const KeyOf& key_of, bool* added) {
    if (2 * (static_cast<size_t>(size_) + 1) > slots_.size()) {
      Rehash(slots_.empty() ? 16 : 2 * slots_.size(), key_of);
    }
    const size_t mask = slots_.size() - 1;
    size_t slot = HashDirectionKey(key) & mask;
    while (slots_[slot] >= 0) {
      if (key_of(slots_[slot]) == key) {
        *added = false;
        return slots_[slot];
      }
      slot = (slot + 1) & mask;
    }
    if (size_ == INT32_MAX) throw std::length_error("more than 2^31 - 1 ids");
    *added = true;
    slots_[slot] = size_;
    return size_++;
  }
  int32_t size() const { return size_; }

 private:
  template <typename KeyOf>
  void Rehash(size_t capacity, const KeyOf& key_of) {
    slots_.assign(capacity, -1);
    for (int32_t id = 0; id < size_; ++id) {
      size_t slot = HashDirectionKey(key_of(id)) & (capacity - 1);
      while (slots_[slot] >= 0) slot = (slot + 1) & (capacity - 1);
      slots_[slot] = id;
    }
  }

  std::vector<int32_t> slots_;  // ids; -1: empty
  int32_t size_ = 0;
};

// The distinct views (wo) of rows given one at a time, with their ids: the
// views a ViewIndex of the same rows has, in the same order.
class ViewIds {
 public:
  int32_t Id(const glm::dvec3& wo) {
    bool added = false;
    const int32_t id = ids_.Id(
        DirectionKeyOf(wo),
        [this](int32_t k) { return DirectionKeyOf(views_[k]); }, &added);
    if (added) views_.push_back(wo);
    return id;
  }
  const std::vector<glm::dvec3>& views() const { return views_; }
  // The views, moved out: the last use of this object.
  std::vector<glm::dvec3> TakeViews() { return std::move(views_); }

 private:
  std::vector<glm::dvec3> views_;
  FirstAppearanceIds ids_;
};

}  // namespace clothfit
