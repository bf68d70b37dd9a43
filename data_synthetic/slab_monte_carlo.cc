#include "data_synthetic/slab_monte_carlo.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <thread>

#include "data_synthetic/synthetic_table.h"
#include "io/input_error.h"
#include "io/text_util.h"

namespace clothfit {
namespace {

constexpr int64_t kChunk = 4096;  // photons per independently seeded chunk
constexpr double kRouletteWeight = 1e-3;
constexpr double kRouletteSurvival = 0.1;
constexpr double kMinSigma = 1e-12;

// Sums of per-photon scores and of their squares, per output and channel.
struct Tally {
  std::vector<glm::dvec3> sum, sum2;
  explicit Tally(size_t outputs = 0)
      : sum(outputs, glm::dvec3(0.0)), sum2(outputs, glm::dvec3(0.0)) {}
  void Add(const Tally& other) {
    for (size_t k = 0; k < sum.size(); ++k) {
      sum[k] += other.sum[k];
      sum2[k] += other.sum2[k];
    }
  }
};

// Output layout of a beam's tally: views on top, views on the bottom,
// direct, reflected, transmitted, then the two histograms.
struct Layout {
  int views = 0, bins = 0;
  int Top(int j) const { return j; }
  int Bottom(int j) const { return views + j; }
  int Direct() const { return 2 * views; }
  int Reflected() const { return 2 * views + 1; }
  int Transmitted() const { return 2 * views + 2; }
  int ReflectedBin(int k) const { return 2 * views + 3 + k; }
  int TransmittedBin(int k) const { return 2 * views + 3 + bins + k; }
  int Size() const { return 2 * views + 3 + 2 * bins; }
};

// One channel group's walk: shared tau, per-channel albedo.
struct Walker {
  double tau;
  glm::dvec3 albedo;
  int max_order;
  Layout layout;
  std::vector<double> inv_mu_o;  // 1 / mu_o per view

  // Scores one photon of a beam with cos(theta_i) = mu_i into `score`
  // (zeroed by the caller).
  void Photon(double mu_i, Random* random,
              std::vector<glm::dvec3>* score) const {
    std::vector<glm::dvec3>& s = *score;
    // Analog direct transmission: the free path outruns the slab.
    const double free_path = -std::log(1.0 - random->Uniform());
    if (free_path * mu_i > tau) s[layout.Direct()] = glm::dvec3(1.0);
    // First flight, forced to collide: downwards from depth 0.
    double depth = 0.0;
    double mu = -mu_i;
    glm::dvec3 weight(1.0);
    double d = tau / mu_i;
    for (int order = 1;; ++order) {
      const double p_collide = -std::expm1(-d);
      weight *= p_collide;
      const double u = random->Uniform();
      const double path = -std::log1p(-u * p_collide);
      depth = std::clamp(depth - path * mu, 0.0, tau);
      // Next-event estimation from the collision at `depth`.
      weight *= albedo;
      const glm::dvec3 w = weight * (1.0 / (4.0 * kPi));
      for (int j = 0; j < layout.views; ++j) {
        const double inv = inv_mu_o[j];
        s[layout.Top(j)] += w * (std::exp(-depth * inv) * inv);
        s[layout.Bottom(j)] += w * (std::exp(-(tau - depth) * inv) * inv);
      }
      if (weight.x <= 0.0 && weight.y <= 0.0 && weight.z <= 0.0) return;
      // Isotropic scattering; the part that leaves without colliding.
      mu = 2.0 * random->Uniform() - 1.0;
      d = mu > 0.0 ? depth / mu : mu < 0.0 ? (tau - depth) / -mu : HUGE_VAL;
      const glm::dvec3 escaped = weight * std::exp(-d);
      const int bin = std::min(layout.bins - 1,
                               static_cast<int>(std::abs(mu) * layout.bins));
      if (mu > 0.0) {
        s[layout.Reflected()] += escaped;
        s[layout.ReflectedBin(bin)] += escaped;
      } else {
        s[layout.Transmitted()] += escaped;
        s[layout.TransmittedBin(bin)] += escaped;
      }
      if (max_order > 0 && order >= max_order) return;
      // Russian roulette on the weight that stays in the slab.
      const glm::dvec3 staying = weight * -std::expm1(-d);
      if (std::max({staying.x, staying.y, staying.z}) < kRouletteWeight) {
        if (random->Uniform() >= kRouletteSurvival) return;
        weight *= 1.0 / kRouletteSurvival;
      }
    }
  }
};

// Calls work(i) for i in [0, count) on `threads` threads (0: all cores).
template <typename Work>
void ParallelFor(int64_t count, int threads, const Work& work) {
  int workers = threads > 0
                    ? threads
                    : static_cast<int>(std::thread::hardware_concurrency());
  workers = static_cast<int>(std::clamp<int64_t>(workers, 1, count));
  std::atomic<int64_t> next{0};
  auto loop = [&]() {
    for (int64_t i = next++; i < count; i = next++) work(i);
  };
  std::vector<std::thread> pool;
  for (int w = 1; w < workers; ++w) pool.emplace_back(loop);
  loop();
  for (std::thread& t : pool) t.join();
}

// Per beam, the tally of `photons` photons of one channel group.
std::vector<Tally> Simulate(const SlabMonteCarloOptions& o, double tau,
                            uint64_t group) {
  Walker walker{tau, o.params.albedo, o.max_order, Layout(), {}};
  walker.layout.views = static_cast<int>(o.theta_o_deg.size());
  walker.layout.bins = o.histogram_bins;
  for (double theta : o.theta_o_deg) {
    walker.inv_mu_o.push_back(1.0 / std::cos(Radians(theta)));
  }
  const size_t outputs = walker.layout.Size();
  const int64_t chunks = (o.photons + kChunk - 1) / kChunk;
  const int64_t beams = static_cast<int64_t>(o.theta_i_deg.size());
  std::vector<Tally> per_chunk(beams * chunks, Tally(outputs));
  ParallelFor(beams * chunks, o.threads, [&](int64_t job) {
    const int64_t beam = job / chunks;
    const int64_t chunk = job % chunks;
    Random random(o.seed ^ (0x9e3779b97f4a7c15ULL *
                            (1 + static_cast<uint64_t>(job) + (group << 40))));
    const double mu_i = std::cos(Radians(o.theta_i_deg[beam]));
    const int64_t n = std::min(kChunk, o.photons - chunk * kChunk);
    std::vector<glm::dvec3> score(outputs);
    Tally& tally = per_chunk[job];
    for (int64_t p = 0; p < n; ++p) {
      std::fill(score.begin(), score.end(), glm::dvec3(0.0));
      walker.Photon(mu_i, &random, &score);
      for (size_t k = 0; k < outputs; ++k) {
        tally.sum[k] += score[k];
        tally.sum2[k] += score[k] * score[k];
      }
    }
  });
  std::vector<Tally> out(beams, Tally(outputs));
  for (int64_t job = 0; job < beams * chunks; ++job) {
    out[job / chunks].Add(per_chunk[job]);
  }
  return out;
}

// Channel `channel` of output k: mean and standard error of the mean.
void Estimate(const Tally& tally, int k, int64_t n, int channel,
              McEstimate* into) {
  const double mean = tally.sum[k][channel] / n;
  const double var = std::max(0.0, tally.sum2[k][channel] / n - mean * mean) *
                     n / std::max<int64_t>(1, n - 1);
  into->mean[channel] = mean;
  into->std_error[channel] = std::sqrt(var / n);
}

void Validate(const SlabMonteCarloOptions& o) {
  const std::string e = ValidateParams(o.params);
  if (!e.empty()) throw InputError("slab Monte Carlo: " + e);
  auto check_angles = [](const std::vector<double>& list, const char* name) {
    if (list.empty()) {
      throw InputError(std::string("slab Monte Carlo: ") + name +
                       ": needs at least one angle");
    }
    for (double a : list) {
      if (!(a >= 0.0 && a <= 89.0)) {
        std::ostringstream msg;
        msg << "slab Monte Carlo: " << name
            << ": angles must be in [0, 89] degrees, got " << a;
        throw InputError(msg.str());
      }
    }
  };
  check_angles(o.theta_i_deg, "theta_i_deg");
  check_angles(o.theta_o_deg, "theta_o_deg");
  if (o.photons < 1 || o.photons > 10000000000LL) {
    throw InputError("slab Monte Carlo: photons: must be in [1, 1e10], got " +
                     std::to_string(o.photons));
  }
  if (o.max_order < 0) {
    throw InputError("slab Monte Carlo: max_order: must be >= 0");
  }
  if (o.histogram_bins < 1 || o.histogram_bins > 1000) {
    throw InputError("slab Monte Carlo: histogram_bins: must be in [1, 1000]");
  }
  if (o.threads < 0)
    throw InputError("slab Monte Carlo: threads: must be >= 0");
}

std::string Rgb(const glm::dvec3& v) {
  return text_util::FormatNumber(v.x, 6) + " " +
         text_util::FormatNumber(v.y, 6) + " " +
         text_util::FormatNumber(v.z, 6);
}

TableRow Row(double theta_i_deg, double theta_o_deg, double phi_o_deg) {
  TableRow row;
  row.wi = DirectionFromAngles(Radians(theta_i_deg), 0.0);
  row.wo = DirectionFromAngles(Radians(theta_o_deg), Radians(phi_o_deg));
  return row;
}

void SetSimulationMeta(const SlabMonteCarloResult& r, MeasurementTable* t) {
  const SlabMonteCarloOptions& o = r.options;
  std::ostringstream sample;
  sample << "Monte Carlo slab, tau " << Rgb(o.params.tau) << ", albedo "
         << Rgb(o.params.albedo) << ", " << o.photons << " photons per beam, "
         << (o.max_order == 0 ? std::string("all orders")
                              : "orders <= " + std::to_string(o.max_order))
         << ", seed " << o.seed;
  t->SetMeta("sample", sample.str());
  t->SetMeta("model", "slab");
  t->SetMeta("tau", Rgb(o.params.tau));
  t->SetMeta("albedo", Rgb(o.params.albedo));
  t->SetMeta("photons", std::to_string(o.photons));
  t->SetMeta("seed", std::to_string(o.seed));
  t->SetMeta("max_order", std::to_string(o.max_order));
}

}  // namespace

SlabMonteCarloResult RunSlabMonteCarlo(const SlabMonteCarloOptions& options) {
  Validate(options);
  const auto t0 = std::chrono::steady_clock::now();
  SlabMonteCarloResult result;
  result.options = options;
  const int views = static_cast<int>(options.theta_o_deg.size());
  const int bins = options.histogram_bins;
  Layout layout{views, bins};
  for (double theta : options.theta_i_deg) {
    SlabMonteCarloBeam beam;
    beam.theta_i_deg = theta;
    beam.reflection.resize(views);
    beam.transmission.resize(views);
    beam.reflected_histogram.resize(bins);
    beam.transmitted_histogram.resize(bins);
    result.beams.push_back(beam);
  }
  // One walk per distinct tau; its channels take their estimates from it.
  for (int c = 0; c < 3; ++c) {
    const double tau = options.params.tau[c];
    bool first = true;
    for (int e = 0; e < c; ++e) first = first && options.params.tau[e] != tau;
    if (!first) continue;
    const std::vector<Tally> tallies =
        Simulate(options, tau, static_cast<uint64_t>(c));
    for (int channel = c; channel < 3; ++channel) {
      if (options.params.tau[channel] != tau) continue;
      for (size_t b = 0; b < tallies.size(); ++b) {
        const Tally& t = tallies[b];
        const int64_t n = options.photons;
        SlabMonteCarloBeam& beam = result.beams[b];
        for (int j = 0; j < views; ++j) {
          Estimate(t, layout.Top(j), n, channel, &beam.reflection[j]);
          Estimate(t, layout.Bottom(j), n, channel, &beam.transmission[j]);
        }
        Estimate(t, layout.Direct(), n, channel, &beam.direct);
        Estimate(t, layout.Reflected(), n, channel, &beam.reflected);
        Estimate(t, layout.Transmitted(), n, channel, &beam.transmitted);
        for (int k = 0; k < bins; ++k) {
          Estimate(t, layout.ReflectedBin(k), n, channel,
                   &beam.reflected_histogram[k]);
          Estimate(t, layout.TransmittedBin(k), n, channel,
                   &beam.transmitted_histogram[k]);
        }
      }
    }
  }
  result.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
          .count();
  return result;
}

std::vector<TableRow> SlabBsdfRows(const std::vector<double>& theta_i_deg,
                                   const std::vector<double>& theta_o_deg) {
  std::vector<TableRow> rows;
  for (double theta_i : theta_i_deg) {
    for (double theta_o : theta_o_deg) rows.push_back(Row(theta_i, theta_o, 0));
    for (double theta_o : theta_o_deg) {
      rows.push_back(Row(theta_i, 180.0 - theta_o, 0.0));
    }
  }
  return rows;
}

std::vector<TableRow> SlabTransmittanceRows(
    const std::vector<double>& theta_i_deg) {
  std::vector<TableRow> rows;
  for (double theta_i : theta_i_deg) {
    TableRow row = Row(theta_i, 180.0 - theta_i, 180.0);
    row.wi = glm::dvec3(0.0, 0.0, 1.0);  // transmittance tables omit wi
    rows.push_back(row);
  }
  return rows;
}

SlabTables SlabModelTables(const SlabParams& params,
                           const std::vector<double>& theta_i_deg,
                           const std::vector<double>& theta_o_deg,
                           const SynthOptions& synth, Random* random) {
  SlabTables out;
  out.bsdf.rows = SlabBsdfRows(theta_i_deg, theta_o_deg);
  SynthesizeValues(params, synth, random, &out.bsdf);
  SynthOptions direct = synth;
  direct.quantity = Quantity::kTransmittance;
  out.transmittance.rows = SlabTransmittanceRows(theta_i_deg);
  SynthesizeValues(params, direct, random, &out.transmittance);
  out.transmittance.channels = SlabTauIsScalar(params) ? 1 : 3;
  return out;
}

MeasurementTable SlabMonteCarloBsdfTable(const SlabMonteCarloResult& result,
                                         Quantity quantity) {
  const SlabMonteCarloOptions& o = result.options;
  MeasurementTable table;
  table.quantity = quantity;
  table.channels = 3;
  table.has_sigma = true;
  table.rows = SlabBsdfRows(o.theta_i_deg, o.theta_o_deg);
  SetSimulationMeta(result, &table);
  size_t i = 0;
  for (const SlabMonteCarloBeam& beam : result.beams) {
    for (const auto* side : {&beam.reflection, &beam.transmission}) {
      for (const McEstimate& e : *side) {
        TableRow& row = table.rows[i++];
        const double scale =
            QuantityFactor(Quantity::kBrdf, quantity, row.wi.z);
        row.value = e.mean * scale;
        row.sigma = glm::max(e.std_error * scale, glm::dvec3(kMinSigma));
      }
    }
    const glm::dvec3 absorbed =
        1.0 - beam.direct.mean - beam.reflected.mean - beam.transmitted.mean;
    char key[64];
    std::snprintf(key, sizeof(key), "energy_theta_i_%g", beam.theta_i_deg);
    table.SetMeta(key, "reflected " + Rgb(beam.reflected.mean) +
                           "; diffusely transmitted " +
                           Rgb(beam.transmitted.mean) + "; direct " +
                           Rgb(beam.direct.mean) + "; absorbed " +
                           Rgb(absorbed));
  }
  return table;
}

MeasurementTable SlabMonteCarloTransmittanceTable(
    const SlabMonteCarloResult& result) {
  const SlabMonteCarloOptions& o = result.options;
  MeasurementTable table;
  table.quantity = Quantity::kTransmittance;
  table.channels = SlabTauIsScalar(o.params) ? 1 : 3;
  table.has_sigma = true;
  table.rows = SlabTransmittanceRows(o.theta_i_deg);
  SetSimulationMeta(result, &table);
  for (size_t b = 0; b < result.beams.size(); ++b) {
    const McEstimate& e = result.beams[b].direct;
    table.rows[b].value = e.mean;
    table.rows[b].sigma = glm::max(e.std_error, glm::dvec3(kMinSigma));
  }
  return table;
}

}  // namespace clothfit
