// clothfit synth --model slab: tables of the optically thin slab
// (docs/models.md) from its single-scattering formulas or from Monte Carlo
// ground truth, and the chart of the formulas' error against Monte Carlo over
// tau x albedo.
#include <iostream>
#include <sstream>

#include "apps/commands.h"
#include "apps/full_binary.h"
#include "apps/progress.h"
#include "bench/slab_error_chart.h"
#include "data_synthetic/slab_monte_carlo.h"
#include "data_synthetic/synthetic_table.h"
#include "io/text_util.h"

namespace clothfit {
namespace {

std::string JoinNumbers(const std::vector<double>& values) {
  std::string out;
  for (size_t i = 0; i < values.size(); ++i) {
    out += (i ? "," : "") + text_util::FormatNumber(values[i], 6);
  }
  return out;
}

// --NAME as polar angles in [0, 89] degrees.
std::vector<double> AngleListOption(const CommandArgs& args,
                                    const std::string& name) {
  const std::vector<double> angles = NumberListOption(args, name);
  for (double a : angles) {
    if (!(a >= 0.0 && a <= 89.0)) {
      std::ostringstream msg;
      msg << "option '--" << name
          << "': angles must be in [0, 89] degrees, got " << a;
      args.Fail(msg.str());
    }
  }
  return angles;
}

// One value for all channels or three.
glm::dvec3 RgbOption(const CommandArgs& args, const std::string& name) {
  const std::vector<double> v = NumberListOption(args, name);
  if (v.size() == 1) return glm::dvec3(v[0]);
  if (v.size() != 3) args.Fail("option '--" + name + "': give 1 or 3 values");
  return glm::dvec3(v[0], v[1], v[2]);
}

SlabParams ParamsOption(const CommandArgs& args) {
  if (args.Has("params") == args.Has("tau")) {
    args.Fail("give exactly one of --params FILE and --tau T");
  }
  SlabParams p;
  if (args.Has("params")) {
    if (args.Has("albedo")) args.Fail("--albedo goes with --tau");
    const ParamFile file = ReadParamFile(args.Get("params"));
    if (!std::holds_alternative<SlabParams>(file.params)) {
      args.Fail(args.Get("params") + ": expected a slab parameter file");
    }
    return std::get<SlabParams>(file.params);
  }
  p.tau = RgbOption(args, "tau");
  p.albedo = RgbOption(args, "albedo");
  const std::string e = ValidateParams(p);
  if (!e.empty()) args.Fail(e);
  return p;
}

int64_t PhotonsOption(const CommandArgs& args, int64_t fallback) {
  if (!args.Has("photons")) return fallback;
  const long n = args.GetInt("photons");
  // 3e8 photons take ~60 s here: 1e9 is some minutes.
  if (n < 1 || n > 1000000000L) {
    args.Fail("option '--photons': must be in [1, 1e9]");
  }
  return n;
}

int ThreadsOption(const CommandArgs& args) {
  const long n = args.GetInt("threads");
  if (n < 0 || n > 256) args.Fail("option '--threads': must be in [0, 256]");
  return static_cast<int>(n);
}

int RunErrorMap(const CommandArgs& args) {
  for (const char* option : {"out", "transmittance", "params", "tau", "albedo",
                             "noise", "single-scatter", "theta-i", "theta-o"}) {
    if (args.Has(option)) {
      args.Fail(std::string("--") + option + " does not go with --error-map");
    }
  }
  SlabErrorMapOptions options;
  options.taus = NumberListOption(args, "taus");
  options.albedos = NumberListOption(args, "albedos");
  options.photons = PhotonsOption(args, options.photons);
  options.seed = static_cast<uint64_t>(args.GetInt("seed"));
  options.threads = ThreadsOption(args);
  const std::string png = args.Get("error-map");
  std::string csv = png.size() > 4 && text_util::HasExtension(png, ".png")
                        ? png.substr(0, png.size() - 4) + ".csv"
                        : png + ".csv";
  if (args.Has("csv")) csv = args.Get("csv");
#ifdef CLOTHFIT_LIGHT
  RunInFullBinary();  // a chart: OpenCV
#else
  const SlabErrorMap map = ComputeSlabErrorMap(options);
  WriteSlabErrorMap(map, png, csv);
  std::cout << "wrote " << png << " and " << csv << " (" << map.cells.size()
            << " cells, " << map.seconds << " s)\n";
  return 0;
#endif
}

}  // namespace

int RunSynthSlab(int argc, char** argv) {
  const SlabMonteCarloOptions mc_defaults;
  const SlabErrorMapOptions map_defaults;
  CommandArgs args(
      "synth",
      "clothfit synth --model slab (--params P.json | --tau T --albedo A) "
      "[--out T.csv] [--transmittance D.csv]\n"
      "       [--mc [--photons N] [--single-scatter] [--threads N]] "
      "[--noise F] [--theta-i LIST] [--theta-o LIST] [--seed S]\n"
      "       clothfit synth --model slab --error-map M.png [--csv M.csv] "
      "[--taus LIST] [--albedos LIST] [--photons N] [--seed S]",
      "Tables of the optically thin slab (docs/models.md; docs/slab.md) for "
      "beams "
      "at --theta-i (phi 0) and views at --theta-o:\n--out gets a BSDF "
      "table with reflection rows (theta_o, wo.z > 0) and transmission rows "
      "(180 - theta_o, wo.z < 0),\n--transmittance a direct-transmittance "
      "table (quantity transmittance, one row per beam seen from the far "
      "side).\nValues: the single-scattering formulas (with --noise), or "
      "with --mc Monte Carlo ground truth with every order of\nscattering "
      "(--single-scatter: the first order only), sigma = its standard "
      "error. Deterministic from --seed for any --threads.\n--error-map: "
      "the formulas' relative rms error against Monte Carlo over --taus x "
      "--albedos, a PNG heat map and its CSV.");
  args.Option("model", "slab", "slab");
  args.Option("params", "P.json", "slab parameter file (docs/formats.md)");
  args.Option("tau", "T[,T,T]", "optical thickness, one or per channel");
  args.Option("albedo", "A[,A,A]", "single-scattering albedo (with --tau)",
              "1");
  args.Option("out", "T.csv", "BSDF table (reflection and transmission)");
  args.Option("transmittance", "D.csv", "direct-transmittance table");
  args.Option("quantity", "Q", "brdf or cosine_weighted", "brdf");
  args.Flag("mc", "Monte Carlo ground truth instead of the formulas");
  args.Flag("single-scatter", "--mc: score single scattering only");
  args.Option("photons", "N",
              "--mc: photons per beam (default " +
                  std::to_string(mc_defaults.photons) + "; " +
                  std::to_string(map_defaults.photons) + " with --error-map)");
  args.Option("theta-i", "LIST", "beam polar angles, degrees in [0, 89]",
              JoinNumbers(mc_defaults.theta_i_deg));
  args.Option("theta-o", "LIST", "view polar angles, degrees in [0, 89]",
              JoinNumbers(mc_defaults.theta_o_deg));
  args.Option("noise", "F", "without --mc: relative noise, [0, 1]", "0");
  args.Option("seed", "S", "random seed (integer)", "1");
  args.Option("threads", "N", "Monte Carlo threads (0: all cores)", "0");
  args.Option("error-map", "M.png",
              "chart of the single-scattering error against Monte Carlo");
  args.Option("csv", "M.csv", "--error-map: its CSV (default M.csv)");
  args.Option("taus", "LIST", "--error-map: optical thicknesses",
              JoinNumbers(map_defaults.taus));
  args.Option("albedos", "LIST", "--error-map: albedos",
              JoinNumbers(map_defaults.albedos));
  if (!args.Parse(argc, argv, 2)) return 0;
  if (args.Get("model") != "slab") args.Fail("--model: expected slab");
  if (args.Has("error-map")) return RunErrorMap(args);
  for (const char* option : {"csv", "taus", "albedos"}) {
    if (args.Has(option)) {
      args.Fail(std::string("--") + option + " goes with --error-map");
    }
  }
  if (!args.Has("out") && !args.Has("transmittance")) {
    args.Fail("give --out T.csv and/or --transmittance D.csv");
  }
  const SlabParams params = ParamsOption(args);
  const Quantity quantity = ModelQuantityOption(args, "quantity");
  const std::vector<double> theta_i = AngleListOption(args, "theta-i");
  const std::vector<double> theta_o = AngleListOption(args, "theta-o");
  const long seed = args.GetInt("seed");
  const bool mc = args.Has("mc");
  for (const char* option : {"photons", "single-scatter"}) {
    if (!mc && args.Has(option)) {
      args.Fail(std::string("--") + option + " goes with --mc");
    }
  }
  if (mc && args.Has("noise")) {
    args.Fail("--noise does not go with --mc (its noise is the simulation's)");
  }

  MeasurementTable bsdf, direct;
  if (mc) {
    SlabMonteCarloOptions options;
    options.params = params;
    options.theta_i_deg = theta_i;
    options.theta_o_deg = theta_o;
    options.photons = PhotonsOption(args, options.photons);
    options.seed = static_cast<uint64_t>(seed);
    options.max_order = args.Has("single-scatter") ? 1 : 0;
    options.threads = ThreadsOption(args);
    const SlabMonteCarloResult result = [&] {
      const progress::Activity activity("synth: Monte Carlo");
      return RunSlabMonteCarlo(options);
    }();
    bsdf = SlabMonteCarloBsdfTable(result, quantity);
    direct = SlabMonteCarloTransmittanceTable(result);
    std::cout << "Monte Carlo: " << options.photons << " photons x "
              << theta_i.size() << " beams in " << result.seconds << " s\n";
  } else {
    SynthOptions synth;
    synth.quantity = quantity;
    synth.noise = args.GetDouble("noise");
    if (!(synth.noise >= 0.0 && synth.noise <= 1.0)) {
      args.Fail("option '--noise': must be in [0, 1], got " +
                args.Get("noise"));
    }
    Random random(static_cast<uint64_t>(seed));
    const SlabTables tables =
        SlabModelTables(params, theta_i, theta_o, synth, &random);
    bsdf = tables.bsdf;
    direct = tables.transmittance;
    std::ostringstream sample;
    sample << "synthetic, single-scattering slab model from "
           << (args.Has("params") ? args.Get("params") : "--tau/--albedo")
           << ", noise " << text_util::FormatNumber(synth.noise, 6) << ", seed "
           << seed;
    bsdf.SetMeta("sample", sample.str());
    direct.SetMeta("sample", sample.str());
  }
  if (args.Has("out")) WriteTable(bsdf, args.Get("out"));
  if (args.Has("transmittance")) WriteTable(direct, args.Get("transmittance"));
  // The formulas' BSDF values (the direct transmittance is exact).
  if (!mc && args.Has("out")) NoteSlabRegime(params);
  return 0;
}

}  // namespace clothfit
