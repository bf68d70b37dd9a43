// The parameter table of a model: one entry per named field of its
// parameter struct (name, unit, meaning, valid range, fit bounds, default,
// source), read by everything that handles parameters - validation, the
// flat vectors of the fits, parameter files, EXR channels, reports. After
// Mitsuba 3's traverse(): each model header defines its entries and
//
//   template <typename T, typename F>
//   void VisitParams(XParamsT<T>& p, F&& f);   // f(info, field) per field
//
// calling f with each entry and a reference to its field (a scalar T, or a
// Vec3<T> for an rgb entry), in table order. Everything below is generic
// over that visitor.
#pragma once

#include <cmath>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "models/math.h"
#include "models/quantity.h"

namespace clothfit {

// An interval of the real line; an end may be open or infinite.
struct Interval {
  double lo = -HUGE_VAL, hi = HUGE_VAL;
  bool lo_open = false, hi_open = false;

  bool Contains(double x) const {
    return std::isfinite(x) && (lo_open ? x > lo : x >= lo) &&
           (hi_open ? x < hi : x <= hi);
  }
};

inline constexpr double kInfinity = HUGE_VAL;

struct ParamInfo {
  const char* name;     // key in parameter files, reports and --fix/--free
  const char* unit;     // e.g. "degrees", "unitless"
  const char* meaning;  // one line
  Interval valid;       // the documented range (ValidateParams)
  // Bounds of a fit (closed). `physical`: they are the parameter's physical
  // range, so that a solution on them is legitimate (kd = 0); otherwise
  // they only limit the search, and a free parameter that ends on one
  // means the solver left the region where the model is meaningful.
  double fit_lo, fit_hi;
  bool physical;
  // The default (per channel for an rgb entry; [0] for a scalar).
  double defaults[3];
  const char* source;  // paper and equation
  int channels;        // 1: one number; 3: r, g, b

  template <typename T>
  T Default() const {
    return T(defaults[0]);
  }
  template <typename T>
  Vec3<T> DefaultRgb() const {
    return Vec3<T>(T(defaults[0]), T(defaults[1]), T(defaults[2]));
  }
};

// What a model is, for code that handles every model alike
// (models/evaluate.h): each model header specialises kModelInfo for its
// parameter type and defines
//
//   template <typename T, typename G>
//   Vec3<T> NativeValue(const XParamsT<T>& p, const Vec3<G>& wi,
//                       const Vec3<G>& wo);
//
// returning the quantity `native` (the one its paper defines); evaluate.h
// converts between f and rho = f |wi.z|, in one place.
struct ModelInfo {
  const char* name;  // the "model" key of parameter files
  Quantity native;   // what NativeValue returns
  // Besides `native`, the direct transmittance D(wo) (Transmittance(p, wo)).
  bool transmittance;
};
template <typename P>
inline constexpr ModelInfo kModelInfo = {nullptr, Quantity::kBrdf, false};

namespace params_internal {

template <typename V>
struct FieldTraits {  // a scalar
  static constexpr int kChannels = 1;
  template <typename U>
  static U& At(U& v, int) {
    return v;
  }
};
template <typename T>
struct FieldTraits<glm::vec<3, T>> {  // rgb
  static constexpr int kChannels = 3;
  template <typename U>
  static auto& At(U& v, int c) {
    return v[c];
  }
};

template <typename V>
constexpr int ChannelsOf() {
  return FieldTraits<std::remove_const_t<V>>::kChannels;
}

// Channel c of a field (the field itself for a scalar).
template <typename V>
auto& Channel(V& v, int c) {
  return FieldTraits<std::remove_const_t<V>>::At(v, c);
}

}  // namespace params_internal

// Visits a const parameter struct (the models define the visitor on
// non-const structs only; it only reads here).
template <typename P, typename F>
void VisitParamsConst(const P& p, F&& f) {
  VisitParams(const_cast<P&>(p), [&](const ParamInfo& info, auto& field) {
    f(info,
      static_cast<const std::remove_reference_t<decltype(field)>&>(field));
  });
}

// The suffix of channel c of an rgb entry in flat names: "_r", "_g", "_b".
inline const char* ChannelSuffix(int c) {
  static const char* const kSuffix[3] = {"_r", "_g", "_b"};
  return kSuffix[c];
}

// Number of entries of the flat layout (an rgb field counts 3).
template <typename P>
int FlatSize(const P& p) {
  int n = 0;
  VisitParamsConst(p, [&](const ParamInfo&, const auto& field) {
    n +=
        params_internal::ChannelsOf<std::remove_reference_t<decltype(field)>>();
  });
  return n;
}

// The flat layout: the fields in table order, rgb fields as r, g, b.
template <typename P, typename T>
void ToArray(const P& p, T* x) {
  VisitParamsConst(p, [&](const ParamInfo&, const auto& field) {
    using V = std::remove_reference_t<decltype(field)>;
    for (int c = 0; c < params_internal::ChannelsOf<V>(); ++c) {
      *x++ = params_internal::Channel(field, c);
    }
  });
}

// Inverse of ToArray: fills the fields of *p from x.
template <typename P, typename T>
void FromArray(const T* x, P* p) {
  VisitParams(*p, [&](const ParamInfo&, auto& field) {
    using V = std::remove_reference_t<decltype(field)>;
    for (int c = 0; c < params_internal::ChannelsOf<V>(); ++c) {
      params_internal::Channel(field, c) = *x++;
    }
  });
}

// The entry of each flat position and its channel (0 for scalars).
struct FlatEntry {
  const ParamInfo* info;
  int channel;
  bool rgb;
  // "eta", "albedo_r": the entry's name with its channel suffix.
  std::string Name() const {
    return rgb ? std::string(info->name) + ChannelSuffix(channel) : info->name;
  }
};

template <typename P>
std::vector<FlatEntry> FlatEntries(const P& p) {
  std::vector<FlatEntry> out;
  VisitParamsConst(p, [&](const ParamInfo& info, const auto& field) {
    using V = std::remove_reference_t<decltype(field)>;
    constexpr int kChannels = params_internal::ChannelsOf<V>();
    for (int c = 0; c < kChannels; ++c)
      out.push_back({&info, c, kChannels > 1});
  });
  return out;
}

// The names of the flat entries, in order.
template <typename P>
std::vector<std::string> FlatNames(const P& p) {
  std::vector<std::string> names;
  for (const FlatEntry& e : FlatEntries(p)) names.push_back(e.Name());
  return names;
}

// A factor on a whole reflectance model (thread, cloth): 1 for absolute
// reflectance; a fit of data on an arbitrary scale (--fit-scale) finds it,
// and the parameter file keeps it ("scale"), so that every evaluation
// reproduces the data the fit saw. Not part of the flat vectors (a fit
// gives it a block of its own).
inline constexpr ParamInfo kModelScale = {
    "scale",
    "unitless",
    "factor on the whole model: 1 for absolute reflectance; the factor "
    "a fit with --fit-scale found for data on an arbitrary scale (at most "
    "1e6, the fit's bound: the model stays finite)",
    {0.0, 1e6, true, false},
    1e-6,
    1e6,
    false,
    {1.0},
    "clothfit",
    1};

// "[lo, hi]", "(0, 90]", ">= 0", "> 0": an interval as a message shows it.
inline std::string DescribeInterval(const Interval& i) {
  std::ostringstream out;
  const bool lo = std::isfinite(i.lo), hi = std::isfinite(i.hi);
  if (lo && hi) {
    out << (i.lo_open ? "(" : "[") << i.lo << ", " << i.hi
        << (i.hi_open ? ")" : "]");
  } else if (lo) {
    out << (i.lo_open ? "> " : ">= ") << i.lo;
  } else if (hi) {
    out << (i.hi_open ? "< " : "<= ") << i.hi;
  } else {
    out << "finite";
  }
  return out.str();
}

// "" when `value` (channel `channel` of an rgb entry, or -1) lies in the
// entry's valid range, else "name: must be in (0, 90], got -1" (rgb:
// "name: component 1 must be >= 0, got -0.2").
inline std::string CheckParam(const ParamInfo& info, double value,
                              int channel = -1) {
  if (info.valid.Contains(value)) return "";
  std::ostringstream msg;
  msg << info.name << ": ";
  if (channel >= 0) msg << "component " << channel << " ";
  const std::string range = DescribeInterval(info.valid);
  const bool word = range.front() == '[' || range.front() == '(';
  msg << "must be " << (word ? "in " : "") << range << ", got " << value;
  return msg.str();
}

// Checks every field against its entry's valid range: "" when all are
// valid, else the message of the first that is not (CheckParam).
template <typename P>
std::string ValidateParams(const P& p) {
  std::string error;
  VisitParamsConst(p, [&](const ParamInfo& info, const auto& field) {
    using V = std::remove_reference_t<decltype(field)>;
    constexpr int kChannels = params_internal::ChannelsOf<V>();
    for (int c = 0; c < kChannels && error.empty(); ++c) {
      error = CheckParam(info, params_internal::Channel(field, c),
                         kChannels > 1 ? c : -1);
    }
  });
  return error;
}

}  // namespace clothfit
