#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "apps/full_binary.h"
#include "apps/progress.h"
#include "holes/hole_texture.h"
#include "io/text_util.h"
#include "models/presets.h"

namespace clothfit {

Quantity ModelQuantityOption(const CommandArgs& args, const std::string& name) {
  const std::string text = args.Get(name);
  const std::optional<Quantity> q = ParseQuantity(text);
  if (!q || *q == Quantity::kTransmittance) {
    args.Fail("option '--" + name +
              "': expected brdf or cosine_weighted, got '" + text + "'");
  }
  return *q;
}

ParamFile LoadModelOption(const CommandArgs& args,
                          const std::string& file_option) {
  if (args.Has(file_option) == args.Has("preset")) {
    args.Fail("give exactly one of --" + file_option +
              " FILE and --preset NAME");
  }
  if (args.Has(file_option)) return ReadParamFile(args.Get(file_option));
  return ParamFile{RequirePreset(args, args.Get("preset")), ""};
}

void WriteTableWithProgress(const MeasurementTable& table,
                            const std::string& path) {
  progress::Task task("writing " + path, "rows");
  WriteTable(table, path,
             [&task](double done, double total) { task.Update(done, total); });
}

ClothParams RequirePreset(const CommandArgs& args, const std::string& name) {
  ClothParams cloth;
  if (!GetPreset(name, &cloth)) {
    args.Fail("unknown preset '" + text_util::EscapeControl(name) + "'" +
              text_util::DidYouMean(name, PresetNames()) +
              "; 'clothfit presets' lists them");
  }
  return cloth;
}

ParamFile LoadEvaluableModel(const CommandArgs& args, Quantity quantity,
                             const std::string& source) {
  ParamFile file = LoadModelOption(args);
  if (std::holds_alternative<HolesModel>(file.params) &&
      !std::get<HolesModel>(file.params).tile) {
    // Its mask, as the file names it (relative to the file's folder).
#ifdef CLOTHFIT_LIGHT
    RunInFullBinary();  // the mask is an image
#else
    file.params = LoadHolesModel(file, args.Get("params"));
#endif
  }
  if (!ModelPredicts(file.params, quantity)) {
    args.Fail(source + ": a " + ModelName(file.params) + " model predicts " +
              (ModelPredicts(file.params, Quantity::kTransmittance) &&
                       !ModelPredicts(file.params, Quantity::kBrdf)
                   ? "transmittance"
                   : "brdf and cosine_weighted values") +
              ", not " + QuantityName(quantity));
  }
  return file;
}

std::vector<std::string> ListOption(const CommandArgs& args,
                                    const std::string& name) {
  std::string text;
  try {
    text = args.Get(name);
  } catch (const InputError&) {
    return {};  // absent, no default
  }
  std::vector<std::string> out;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    out.push_back(text.substr(start, comma - start));
    if (out.back().empty()) {
      args.Fail("option '--" + name + "': empty item in '" + text +
                "' (items are separated by single commas)");
    }
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

std::vector<double> NumberListOption(const CommandArgs& args,
                                     const std::string& name) {
  std::vector<double> out;
  for (const std::string& item : ListOption(args, name)) {
    char* end = nullptr;
    const double x = std::strtod(item.c_str(), &end);
    if (*end != '\0' || !std::isfinite(x)) {
      args.Fail("option '--" + name + "': cannot parse '" + item +
                "' as a finite number");
    }
    out.push_back(x);
  }
  if (out.empty()) args.Fail("option '--" + name + "': needs a number");
  return out;
}

namespace {

// "0.1" when the channels agree, else "0.1,0.2,0.4".
std::string FormatRgb(const glm::dvec3& v) {
  char text[96];
  if (v.x == v.y && v.x == v.z) {
    std::snprintf(text, sizeof(text), "%g", v.x);
  } else {
    std::snprintf(text, sizeof(text), "%g,%g,%g", v.x, v.y, v.z);
  }
  return text;
}

}  // namespace

void NoteSlabRegime(const SlabParams& p) {
  const double error = SlabParamsSingleScatterError(p);
  if (!(error > kSlabRegimeTolerance)) return;
  const double max_tau = std::max({p.tau.x, p.tau.y, p.tau.z});
  char estimate[160];
  std::snprintf(estimate, sizeof(estimate),
                "estimated error A q(tau) = %.2g %% > %.0f %%%s", 100.0 * error,
                100.0 * kSlabRegimeTolerance,
                max_tau < kSlabPaperTauLimit
                    ? ", although tau is below the paper's bound 0.2"
                    : "");
  std::cerr << "note: tau = " << FormatRgb(p.tau)
            << ", albedo = " << FormatRgb(p.albedo)
            << " are outside the slab model's single-scattering regime ("
            << estimate
            << "): its f_r, f_t lack multiple scattering and are too low; "
               "'clothfit synth --model slab --mc' gives every order "
               "(docs/slab.md)\n";
}

std::string ModelArgument(int argc, char** argv, int first) {
  for (int i = first; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--model=", 0) == 0) return a.substr(8);
    if (a == "--model" && i + 1 < argc) return argv[i + 1];
  }
  return "";
}

}  // namespace clothfit
