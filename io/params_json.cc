#include "io/params_json.h"

#include <cmath>
#include <initializer_list>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <type_traits>
#include <utility>
#include <vector>

#include "io/atomic_file.h"
#include "io/holes_tile_json_internal.h"
#include "io/input_error.h"
#include "io/json_object_reader_internal.h"
#include "io/json_text_internal.h"
#include "io/text_util.h"

namespace clothfit {
namespace {

using io_internal::json;
using io_internal::ObjectReader;

// The keys of a parameter table (models/params.h): a number for a scalar
// entry, a number or 3 numbers for an rgb entry. Keys in `optional` may be
// absent (the entry keeps its default).
template <typename P>
P ReadParamKeys(ObjectReader& r,
                std::initializer_list<const char*> optional = {}) {
  P p;
  VisitParams(p, [&](const ParamInfo& info, auto& field) {
    for (const char* name : optional) {
      if (std::string(name) == info.name && !r.Has(name)) return;
    }
    if constexpr (std::is_same_v<std::decay_t<decltype(field)>, double>) {
      field = r.Number(info.name);
    } else {
      field = r.Rgb(info.name);
    }
  });
  return p;
}

template <typename P>
void WriteParamKeys(const P& p, json* j) {
  VisitParamsConst(p, [&](const ParamInfo& info, const auto& field) {
    if constexpr (std::is_same_v<std::decay_t<decltype(field)>, double>) {
      (*j)[info.name] = field;
    } else {
      (*j)[info.name] = {field.x, field.y, field.z};
    }
  });
}

// Range errors name the key by its path: "threads[0].kd: must be ..." ->
// key 'threads[0].kd'.
[[noreturn]] void FailValidation(const std::string& file,
                                 const std::string& message) {
  const size_t colon = message.find(": ");
  if (colon == std::string::npos) throw InputError(file + ": " + message);
  throw InputError(file + ": key '" + message.substr(0, colon) +
                   "': " + message.substr(colon + 2));
}

ClothThread ReadClothThread(const json& object, const std::string& file,
                            const std::string& path) {
  ObjectReader r(object, file, path);
  ClothThread th;
  const std::string dir = r.String("direction");
  if (dir == "u") {
    th.direction = ThreadDirection::kU;
  } else if (dir == "v") {
    th.direction = ThreadDirection::kV;
  } else {
    r.Fail(r.Path("direction"), "must be \"u\" or \"v\", got \"" + dir + "\"");
  }
  th.coverage = r.Number("coverage");
  const bool explicit_samples = r.Has("offsets_deg");
  const bool curve =
      r.Has("curve_offsets_deg") || r.Has("curve_lengths") || r.Has("samples");
  if (explicit_samples && curve) {
    r.Fail(r.Path("offsets_deg"),
           "give either offsets_deg or a tangent curve (curve_offsets_deg, "
           "curve_lengths, samples), not both");
  }
  if (explicit_samples) {
    th.offsets_deg = r.NumberArray("offsets_deg");
  } else {
    th.curve.offsets_deg = r.NumberArray("curve_offsets_deg");
    th.curve.lengths = r.NumberArray("curve_lengths");
    const double samples = r.Number("samples");
    if (samples != std::floor(samples)) {
      r.Fail(r.Path("samples"), "must be an integer");
    }
    th.curve.samples = static_cast<int>(std::max(-1.0, std::min(samples, 1e9)));
    const std::string e = ValidateTangentCurve(th.curve);
    if (!e.empty()) FailValidation(file, path + "." + e);
    th.offsets_deg = SampleTangentCurve(th.curve);
  }
  th.params = ReadParamKeys<ThreadParams>(r);
  r.Finish();
  return th;
}

// The energy bound's tables (models/energy_bound.h) under "energy_bound":
// {"light": [...], "view": [...]}; null when the file has none (the
// paper's model).
std::shared_ptr<const EnergyBound> ReadEnergyBound(ObjectReader& r,
                                                   const std::string& file) {
  if (!r.Has("energy_bound")) return nullptr;
  ObjectReader b(r.Get("energy_bound"), file, "energy_bound");
  auto bound = std::make_shared<EnergyBound>();
  bound->light = b.NumberArray("light");
  bound->view = b.NumberArray("view");
  b.Finish();
  const std::string e = ValidateEnergyBound(*bound);
  if (!e.empty()) r.Fail("energy_bound", e);
  return bound;
}

void WriteEnergyBound(const std::shared_ptr<const EnergyBound>& bound,
                      json* j) {
  if (bound) {
    (*j)["energy_bound"] = {{"light", bound->light}, {"view", bound->view}};
  }
}

// Like json::dump(2), but arrays of scalars stay on one line.
void AppendPretty(const json& j, int indent, std::string* out) {
  const std::string pad(indent + 2, ' ');
  if (j.is_object() && !j.empty()) {
    *out += "{\n";
    bool first = true;
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (!first) *out += ",\n";
      first = false;
      *out += pad + json(it.key()).dump() + ": ";
      AppendPretty(it.value(), indent + 2, out);
    }
    *out += "\n" + std::string(indent, ' ') + "}";
    return;
  }
  if (j.is_array() && !j.empty()) {
    bool scalars = true;
    for (const json& e : j) scalars = scalars && !e.is_structured();
    *out += scalars ? "[" : "[\n";
    for (size_t i = 0; i < j.size(); ++i) {
      if (i > 0) *out += scalars ? ", " : ",\n";
      if (!scalars) *out += pad;
      AppendPretty(j[i], indent + 2, out);
    }
    *out += scalars ? "]" : "\n" + std::string(indent, ' ') + "]";
    return;
  }
  *out += j.dump();
}

}  // namespace

std::optional<HoleMethod> ParseHoleMethod(const std::string& text) {
  for (HoleMethod m : {HoleMethod::kAlgorithm31, HoleMethod::kExtension}) {
    if (text == HoleMethodName(m)) return m;
  }
  return std::nullopt;
}

ParamFile ParseParamFile(const std::string& text, const std::string& name) {
  const json root = ParseJsonText<json>(text, name);
  ObjectReader r(root, name, "");
  ParamFile out;
  const std::string model = r.String("model");
  if (model == "thread") {
    ThreadParams p = ReadParamKeys<ThreadParams>(r);
    if (r.Has(kModelScale.name)) p.scale = r.Number(kModelScale.name);
    p.energy_bound = ReadEnergyBound(r, name);
    const std::string e = ValidateModel(p);
    if (!e.empty()) FailValidation(name, e);
    out.params = p;
  } else if (model == "cloth") {
    ClothParams c;
    const json& threads = r.Get("threads");
    if (!threads.is_array()) r.Fail("threads", "must be an array of objects");
    for (size_t j = 0; j < threads.size(); ++j) {
      c.threads.push_back(ReadClothThread(
          threads[j], name, "threads[" + std::to_string(j) + "]"));
    }
    // The weave's optional freedoms (models/microcylinder_cloth.h): absent
    // keys are the paper's model.
    if (r.Has(kClothRotation.name)) {
      c.rotation_deg = r.Number(kClothRotation.name);
    }
    if (r.Has(kClothDiffuse.name)) c.diffuse = r.Rgb(kClothDiffuse.name);
    if (r.Has(kModelScale.name)) c.scale = r.Number(kModelScale.name);
    c.energy_bound = ReadEnergyBound(r, name);
    const std::string e = ValidateClothParams(c);
    if (!e.empty()) FailValidation(name, e);
    out.params = c;
  } else if (model == "lafortune") {
    LafortuneModel m;
    m.params.diffuse = r.Rgb(kLafortuneDiffuse.name);
    const json& lobes = r.Get("lobes");
    if (!lobes.is_array()) r.Fail("lobes", "must be an array of objects");
    for (size_t k = 0; k < lobes.size(); ++k) {
      ObjectReader lr(lobes[k], name, "lobes[" + std::to_string(k) + "]");
      m.params.lobes.push_back(ReadParamKeys<LafortuneLobe>(lr));
      lr.Finish();
    }
    if (r.Has("normal")) {  // the texel's average normal (lobes' frame)
      const std::vector<double> n = r.NumberArray("normal");
      const glm::dvec3 v =
          n.size() == 3 ? glm::dvec3(n[0], n[1], n[2]) : glm::dvec3(0.0);
      if (!(n.size() == 3 && v.z > 0.0)) {
        r.Fail("normal", "must be 3 numbers [x, y, z] with z > 0");
      }
      m.normal = glm::normalize(v);
    }
    if (r.Has("lut")) {
      ObjectReader lut(r.Get("lut"), name, "lut");
      const json& views = lut.Get("views");
      const json& colors = lut.Get("color");
      if (!views.is_array() || !colors.is_array()) {
        lut.Fail("lut",
                 "views and color must be arrays of [x, y, z] / [r, g, b]");
      }
      auto vec3_at = [&](const json& list, size_t k, const std::string& key) {
        const std::string where = "lut." + key + "[" + std::to_string(k) + "]";
        const json& e = list[k];
        if (!e.is_array() || e.size() != 3) r.Fail(where, "must be 3 numbers");
        glm::dvec3 v;
        for (int c = 0; c < 3; ++c) {
          if (!e[c].is_number()) r.Fail(where, "must be 3 numbers");
          v[c] = e[c].get<double>();
        }
        return v;
      };
      for (size_t k = 0; k < views.size(); ++k) {
        m.lut.views.push_back(vec3_at(views, k, "views"));
      }
      for (size_t k = 0; k < colors.size(); ++k) {
        m.lut.color.push_back(vec3_at(colors, k, "color"));
      }
      m.lut.alpha = lut.NumberArray("alpha");
      if (lut.Has("interpolation") &&
          lut.String("interpolation") != kLutInterpolation) {
        lut.Fail("lut.interpolation",
                 std::string("only \"") + kLutInterpolation + "\" is known");
      }
      lut.Finish();
      for (glm::dvec3& v : m.lut.views) {
        const double len = glm::length(v);
        if (len > 0.0) v /= len;
      }
    }
    std::string e = ValidateLafortuneParams(m.params);
    if (e.empty()) e = ValidateViewTable(m.lut);
    if (!e.empty()) FailValidation(name, e);
    out.params = m;
  } else if (model == "slab") {
    const SlabParams p = ReadParamKeys<SlabParams>(r);
    const std::string e = ValidateParams(p);
    if (!e.empty()) FailValidation(name, e);
    out.params = p;
  } else if (model == "sheen") {
    const SheenParams p = ReadParamKeys<SheenParams>(r);
    const std::string e = ValidateParams(p);
    if (!e.empty()) FailValidation(name, e);
    out.params = p;
  } else if (model == "holes") {
    HolesModel h;
    h.params = ReadParamKeys<HolesParams>(r, {kHolesWallColor.name});
    const std::string e = ValidateParams(h.params);
    if (!e.empty()) FailValidation(name, e);
    if (r.Has("mask")) out.holes.path = r.String("mask");
    out.holes.threshold = r.NumberOr("threshold", 0.5);
    if (!(out.holes.threshold > 0.0 && out.holes.threshold <= 1.0)) {
      r.Fail("threshold", "must be in (0, 1]");
    }
    if (r.Has("method")) {
      out.holes.method = ParseHoleMethod(r.String("method"));
      if (!out.holes.method) {
        r.Fail("method", "must be \"alg31\" or \"extension\"");
      }
    }
    if (r.Has("tile")) {
      h.tile = std::make_shared<const HolesTile>(io_internal::ReadHolesTile(
          r.Get("tile"), name,
          out.holes.method.value_or(HoleMethod::kExtension)));
    }
    out.params = h;
  } else {
    r.Fail("model", "unknown model \"" + model +
                        "\" (expected \"thread\", \"cloth\", "
                        "\"lafortune\", \"slab\", \"holes\" or "
                        "\"sheen\")");
  }
  if (r.Has("fit")) out.fit_json = r.Get("fit").dump();
  r.Finish();
  return out;
}

ParamFile ReadParamFile(const std::string& path) {
  return ParseParamFile(ReadFileToString(path), path);
}

std::string FormatParamFile(const ParamFile& file) {
  json j;
  j["model"] = ModelName(file.params);
  auto rgb = [](const glm::dvec3& v) { return json{v.x, v.y, v.z}; };
  if (const auto* p = std::get_if<ThreadParams>(&file.params)) {
    WriteParamKeys(*p, &j);
    if (p->scale != 1.0) j[kModelScale.name] = p->scale;
    WriteEnergyBound(p->energy_bound, &j);
  } else if (const auto* m = std::get_if<LafortuneModel>(&file.params)) {
    j[kLafortuneDiffuse.name] = rgb(m->params.diffuse);
    json lobes = json::array();
    for (const LafortuneLobe& lobe : m->params.lobes) {
      json l;
      WriteParamKeys(lobe, &l);
      lobes.push_back(l);
    }
    j["lobes"] = lobes;
    j["normal"] = rgb(m->normal);
    if (!m->lut.views.empty()) {
      json views = json::array(), colors = json::array();
      for (size_t k = 0; k < m->lut.views.size(); ++k) {
        views.push_back(rgb(m->lut.views[k]));
        colors.push_back(rgb(m->lut.color[k]));
      }
      j["lut"] = {{"interpolation", kLutInterpolation},
                  {"views", views},
                  {"color", colors},
                  {"alpha", m->lut.alpha}};
    }
  } else if (const auto* p = std::get_if<SlabParams>(&file.params)) {
    WriteParamKeys(*p, &j);
    if (SlabTauIsScalar(*p)) j[kSlabTau.name] = p->tau.x;
  } else if (const auto* p = std::get_if<SheenParams>(&file.params)) {
    WriteParamKeys(*p, &j);
  } else if (const auto* h = std::get_if<HolesModel>(&file.params)) {
    WriteParamKeys(h->params, &j);
    if (!file.holes.path.empty()) j["mask"] = file.holes.path;
    j["threshold"] = file.holes.threshold;
    // The method the tile was made for, when the file names none: the
    // reader evaluates the tile with the file's method.
    std::optional<HoleMethod> method = file.holes.method;
    if (!method && h->tile) method = h->tile->method;
    if (method) j["method"] = HoleMethodName(*method);
    if (h->tile && h->tile->texels.counts.size() <= kMaxStoredTileTexels) {
      j["tile"] = io_internal::FormatHolesTile(*h->tile);
    }
  } else {
    const ClothParams& c = std::get<ClothParams>(file.params);
    json threads = json::array();
    for (const ClothThread& th : c.threads) {
      json t;
      t["direction"] = th.direction == ThreadDirection::kU ? "u" : "v";
      t["coverage"] = th.coverage;
      if (th.curve.samples > 0) {
        t["curve_offsets_deg"] = th.curve.offsets_deg;
        t["curve_lengths"] = th.curve.lengths;
        t["samples"] = th.curve.samples;
      } else {
        t["offsets_deg"] = th.offsets_deg;
      }
      WriteParamKeys(th.params, &t);
      threads.push_back(t);
    }
    j["threads"] = threads;
    if (c.rotation_deg != 0.0) j[kClothRotation.name] = c.rotation_deg;
    if (c.diffuse != glm::dvec3(0.0)) j[kClothDiffuse.name] = rgb(c.diffuse);
    if (c.scale != 1.0) j[kModelScale.name] = c.scale;
    WriteEnergyBound(c.energy_bound, &j);
  }
  if (!file.fit_json.empty()) j["fit"] = json::parse(file.fit_json);
  std::string out;
  AppendPretty(j, 0, &out);
  return out + "\n";
}

void WriteParamFile(const ParamFile& file, const std::string& path) {
  // What is written must read back: the model's ranges keep it finite over
  // the hemisphere (a holes file's mask is checked where it is read).
  const std::string e =
      std::holds_alternative<HolesModel>(file.params)
          ? ValidateParams(std::get<HolesModel>(file.params).params)
          : ValidateModel(file.params);
  if (!e.empty()) throw InputError(path + ": not written: " + e);
  WriteFileAtomically(path, FormatParamFile(file));
}

}  // namespace clothfit
