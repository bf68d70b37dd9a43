#include <algorithm>
#include <cmath>

#include "fitting/cloth_weave_internal.h"

namespace clothfit {

ClothVector::ClothVector(const ClothParams& layout) {
  size_t next = 0;
  for (const ClothThread& th : layout.threads) {
    start_.push_back(next);
    samples_.push_back(th.offsets_deg.size());
    next += kThreadFlatSize + 2 + th.offsets_deg.size();
  }
  cloth_ = next;
}

std::vector<int> ClothVector::BlockSizes() const {
  std::vector<int> sizes;
  for (size_t j = 0; j < Threads(); ++j) {
    sizes.push_back(kThreadFlatSize);
    sizes.push_back(static_cast<int>(2 + samples_[j]));
  }
  sizes.push_back(kClothBlockSize);
  sizes.push_back(1);
  return sizes;
}

namespace {

// An angle in degrees moved into (-180, 180].
double WrapDegrees(double deg) {
  double r = std::fmod(deg, 360.0);
  if (r <= -180.0) r += 360.0;
  if (r > 180.0) r -= 360.0;
  return r;
}

}  // namespace

std::vector<double> ReportedVector(const Weave& weave, std::vector<double> x) {
  StickToCoverage<double>(
      weave, [&](size_t j) -> double& { return x[weave.vector.Coverage(j)]; });
  double& rotation = x[weave.vector.Rotation()];
  rotation = WrapDegrees(rotation);
  return x;
}

std::vector<double> CoverageToStick(const Weave& weave, std::vector<double> x) {
  double left = weave.remaining;
  for (size_t j : weave.stick) {
    double& entry = x[weave.vector.Coverage(j)];
    const double u = left > 0.0 ? std::clamp(entry / left, 0.0, 1.0) : 0.0;
    entry = u;
    left *= 1.0 - u;
  }
  return x;
}

std::vector<double> ClothToVector(const ClothParams& c) {
  std::vector<double> x;
  for (const ClothThread& th : c.threads) {
    double p[kThreadFlatSize];
    ToArray(th.params, p);
    x.insert(x.end(), p, p + kThreadFlatSize);
    x.push_back(th.coverage);
    x.push_back(1.0);  // offset_scale
    x.insert(x.end(), th.offsets_deg.begin(), th.offsets_deg.end());
  }
  x.push_back(c.rotation_deg);
  for (int k = 0; k < 3; ++k) x.push_back(c.diffuse[k]);
  x.push_back(1.0);  // scale
  return x;
}

ClothParams ClothFromVector(const Weave& weave, const std::vector<double>& x) {
  const ClothVector& v = weave.vector;
  ClothParams c = weave.layout;
  for (size_t j = 0; j < c.threads.size(); ++j) {
    ClothThread& th = c.threads[j];
    FromArray(x.data() + v.Thread(j), &th.params);
    if (weave.shared_albedo) {
      th.params.albedo = glm::dvec3(x[4], x[5], x[6]);
    }
    th.coverage = x[v.Coverage(j)];
    bool moved = false;
    for (size_t k = 0; k < th.offsets_deg.size(); ++k) {
      const double o = x[v.OffsetScale(j)] * x[v.Offset(j, k)];
      moved = moved || o != th.offsets_deg[k];
      th.offsets_deg[k] = o;
    }
    // Moved samples no longer follow the file's tangent curve: the file
    // then lists them (offsets_deg).
    if (moved) th.curve = TangentCurve();
  }
  c.rotation_deg = x[v.Rotation()];
  for (int k = 0; k < 3; ++k) c.diffuse[k] = x[v.Diffuse(k)];
  c.scale = x[v.Scale()];  // 1 unless fitted (--fit-scale)
  return c;
}

// The fit-only entry of a thread: a factor on all of its tangent offsets,
// keeping the weave's shape; bounded so that the largest offset stays
// within [-90, 90] degrees.
inline constexpr ParamInfo kOffsetScale = {
    "offset_scale",
    "unitless",
    "factor on all of a thread's tangent offsets (the weave's shape kept)",
    {0.0, kInfinity},
    0.0,
    1.0,
    false,
    {1.0},
    "clothfit",
    1};

std::vector<ParameterSpec> ClothSpecs(const ClothParams& layout) {
  std::vector<ParameterSpec> specs;
  auto fixed = [&](const ParamInfo& info, const std::string& name) {
    specs.push_back(SpecOf(info, name));
    specs.back().free = false;
  };
  for (size_t j = 0; j < layout.threads.size(); ++j) {
    const std::string prefix = ClothThreadPrefix(j);
    for (ParameterSpec& spec : ParameterSpecs(ThreadParams(), prefix)) {
      specs.push_back(spec);
    }
    // eta is fixed by default: the data rarely separate it from kd/albedo.
    specs[specs.size() - kThreadFlatSize].free = false;
    double largest = 0.0;
    for (double o : layout.threads[j].offsets_deg) {
      largest = std::max(largest, std::abs(o));
    }
    fixed(kClothCoverage, prefix + kClothCoverage.name);
    fixed(kOffsetScale, prefix + kOffsetScale.name);
    specs.back().upper = largest > 0.0 ? kClothOffsets.fit_hi / largest : 1.0;
    specs.back().physical_upper = true;  // the largest offset at 90 degrees
    for (size_t k = 0; k < layout.threads[j].offsets_deg.size(); ++k) {
      fixed(kClothOffsets,
            prefix + kClothOffsets.name + "[" + std::to_string(k) + "]");
    }
  }
  fixed(kClothRotation, kClothRotation.name);
  for (const char* channel : {"_r", "_g", "_b"}) {
    fixed(kClothDiffuse, std::string(kClothDiffuse.name) + channel);
  }
  fixed(kFitScale, kFitScale.name);
  return specs;
}

void FillRowSamples(const ClothParams& cloth,
                    const std::vector<bool>& eta_fixed, const TableRow& row,
                    RowSamples* out) {
  out->per_thread.resize(cloth.threads.size());
  out->fresnel.resize(cloth.threads.size());
  for (size_t j = 0; j < cloth.threads.size(); ++j) {
    out->per_thread[j].clear();  // keeps the capacity: no allocation
    out->fresnel[j].clear();
  }
  if (!IsReflectionRow(row)) return;  // reflection only
  for (size_t j = 0; j < cloth.threads.size(); ++j) {
    const ClothThread& th = cloth.threads[j];
    const ThreadLobeParams<double> lobe_params(th.params);
    for (double offset : th.offsets_deg) {
      const TangentSample<double> sample = ComputeTangentSample(
          th.direction, cloth.rotation_deg, offset, row.wi, row.wo);
      out->per_thread[j].push_back(sample);
      if (eta_fixed[j]) {
        out->fresnel[j].push_back(
            sample.weight > 0.0 ? ThreadFresnel(sample.geometry, lobe_params)
                                : 0.0);
      }
    }
  }
}

RowSamples ComputeRowSamples(const ClothParams& cloth,
                             const std::vector<bool>& eta_fixed,
                             const TableRow& row) {
  RowSamples out;
  FillRowSamples(cloth, eta_fixed, row, &out);
  return out;
}

}  // namespace clothfit
