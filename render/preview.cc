#include "render/preview.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "io/image_stack.h"
#include "io/input_error.h"

namespace clothfit {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A direction in the frame (x_s, y_s, n).
glm::dvec3 ToLocal(const glm::dvec3& w, const glm::dvec3& x_s,
                   const glm::dvec3& y_s, const glm::dvec3& n) {
  return glm::dvec3(glm::dot(w, x_s), glm::dot(w, y_s), glm::dot(w, n));
}

PreviewImage Blank(int panels, int size) {
  PreviewImage image;
  image.width = panels * size;
  image.height = size;
  image.panel_size = size;
  image.panel_warp_deg.assign(panels, kNaN);
  image.pixels.assign(size_t(image.width) * image.height, glm::dvec3(0.0));
  return image;
}

double Checker(const glm::dvec2& p) {
  const int cx = static_cast<int>(std::floor(p.x / 0.3));
  const int cy = static_cast<int>(std::floor(p.y / 0.3));
  return (cx + cy) % 2 == 0 ? kCheckerLight : kCheckerDark;
}

// Where the camera ray through p meets the panel tilted by `tilt` (radians)
// about +y: the hit point and the panel's frame; false when the ray misses
// the panel's square.
struct PanelHit {
  glm::dvec3 point, x_s, y_s, n;
};

bool HitPanel(const glm::dvec2& p, double tilt, PanelHit* hit) {
  constexpr double kHalf = 0.8;
  hit->n = glm::dvec3(std::sin(tilt), 0.0, std::cos(tilt));
  hit->x_s = glm::dvec3(std::cos(tilt), 0.0, -std::sin(tilt));
  hit->y_s = glm::dvec3(0.0, 1.0, 0.0);
  // The ray (p.x, p.y, z) meets n . P = 0 at z = -p.x tan(tilt).
  hit->point = glm::dvec3(p.x, p.y, -p.x * std::tan(tilt));
  return std::abs(glm::dot(hit->point, hit->x_s)) <= kHalf &&
         std::abs(p.y) <= kHalf;
}

// The light at `position` seen from `point`: direction and I / r^2.
void LightAt(const glm::dvec3& position, double intensity,
             const glm::dvec3& point, glm::dvec3* wi, double* irradiance) {
  const glm::dvec3 d = position - point;
  const double r2 = glm::dot(d, d);
  *wi = d / std::sqrt(r2);
  *irradiance = intensity / r2;
}

// The three cylinder panels: title and the warp's angle from the axis.
struct ThreadLayout {
  const char* title;
  double warp_deg;
};
constexpr ThreadLayout kThreadLayouts[] = {
    {"warp vertical", 0.0}, {"warp horizontal", 90.0}, {"warp diagonal", 45.0}};

}  // namespace

glm::dvec2 PanelPoint(int i, int j, int size) {
  return glm::dvec2((i + 0.5) / size * 2.0 - 1.0,
                    1.0 - (j + 0.5) / size * 2.0) *
         kPanelExtent;
}

PreviewImage RenderCylinders(const ModelParams& params,
                             const PreviewOptions& options) {
  return RenderCylinders(
      [&params](const glm::dvec3& wi, const glm::dvec3& wo, const glm::dvec2&,
                double) {
        return Evaluate(params, wi, wo, Quantity::kCosineWeighted);
      },
      options);
}

PreviewImage RenderCylinders(const SurfaceRho& rho,
                             const PreviewOptions& options) {
  const int size = options.size;
  PreviewImage image = Blank(3, size);
  const double d = options.light_distance;
  const glm::dvec3 light = options.light * d;
  const glm::dvec3 wo(0.0, 0.0, 1.0);
  const double pixel = 2.0 * kPanelExtent / size;
  for (int panel = 0; panel < 3; ++panel) {
    image.panel_titles.push_back(kThreadLayouts[panel].title);
    image.panel_warp_deg[panel] = kThreadLayouts[panel].warp_deg;
    const double alpha = Radians(kThreadLayouts[panel].warp_deg);
    const double ca = std::cos(alpha), sa = std::sin(alpha);
    for (int j = 0; j < size; ++j) {
      for (int i = 0; i < size; ++i) {
        const glm::dvec2 p = PanelPoint(i, j, size);
        if (!(std::abs(p.x) < 1.0)) continue;
        const double z = std::sqrt(1.0 - p.x * p.x);
        const glm::dvec3 point(p.x, p.y, z), n(p.x, 0.0, z);
        const glm::dvec3 axis(0.0, 1.0, 0.0), around(z, 0.0, -p.x);
        const glm::dvec3 x_s = ca * axis + sa * around;
        const glm::dvec3 y_s = glm::cross(n, x_s);  // sa axis - ca around
        // Axis coordinate and arc length, turned like x_s and y_s.
        const double arc = std::asin(p.x);
        const glm::dvec2 uv(ca * p.y + sa * arc, sa * p.y - ca * arc);
        glm::dvec3 wi;
        double irradiance = 0.0;
        LightAt(light, d * d, point, &wi, &irradiance);
        image.At(panel * size + i, j) =
            rho(ToLocal(wi, x_s, y_s, n), ToLocal(wo, x_s, y_s, n), uv,
                pixel / z) *
            irradiance;
      }
    }
  }
  return image;
}

int MipLevelForFootprint(double footprint, double tile, int base_width,
                         int levels) {
  const double texels = footprint * base_width / tile;
  if (!(texels > 1.0)) return 0;  // also NaN
  const double level = std::round(std::log2(texels));
  return static_cast<int>(std::min(level, double(levels - 1)));
}

SurfaceRho MipmapRho(const Material& material, double tile) {
  return [material, tile](const glm::dvec3& wi, const glm::dvec3& wo,
                          const glm::dvec2& uv, double footprint) {
    const int level = MipLevelForFootprint(footprint, tile, material.Width(0),
                                           material.Levels());
    const double s = uv.x / tile - std::floor(uv.x / tile);
    const double t = uv.y / tile - std::floor(uv.y / tile);
    return material.Rho(wi, wo, s, t, level);
  };
}

PreviewImage RenderSlab(const SlabParams& params,
                        const PreviewOptions& options) {
  const int size = options.size;
  PreviewImage image = Blank(2, size);
  image.panel_titles = {"front-lit", "back-lit"};
  const double d = options.light_distance;
  const glm::dvec3& l = options.light;
  const glm::dvec3 lights[2] = {l * d, glm::dvec3(l.x, l.y, -l.z) * d};
  const glm::dvec3 wo(0.0, 0.0, 1.0);
  const double tilt = Radians(options.tilt_deg);
  for (int panel = 0; panel < 2; ++panel) {
    for (int j = 0; j < size; ++j) {
      for (int i = 0; i < size; ++i) {
        const glm::dvec2 p = PanelPoint(i, j, size);
        glm::dvec3 value(Checker(p));
        PanelHit hit;
        if (HitPanel(p, tilt, &hit)) {
          glm::dvec3 wi;
          double irradiance = 0.0;
          LightAt(lights[panel], d * d, hit.point, &wi, &irradiance);
          const glm::dvec3 wo_l = ToLocal(wo, hit.x_s, hit.y_s, hit.n);
          value = value * SlabDirectTransmittance(params, wo_l) +
                  Evaluate(params, ToLocal(wi, hit.x_s, hit.y_s, hit.n), wo_l,
                           Quantity::kCosineWeighted) *
                      irradiance;
        }
        image.At(panel * size + i, j) = value;
      }
    }
  }
  return image;
}

PreviewImage RenderHoles(const HolesModel& model,
                         const PreviewOptions& options) {
  const int size = options.size;
  PreviewImage image = Blank(3, size);
  const double d = options.light_distance;
  const glm::dvec3 wo(0.0, 0.0, 1.0);
  for (int panel = 0; panel < 3; ++panel) {
    const double tilt_deg = panel * options.tilt_deg;
    image.panel_titles.push_back("tilt " + std::to_string(int(tilt_deg)) +
                                 " deg");
    PanelHit probe;
    HitPanel(glm::dvec2(0.0), Radians(tilt_deg), &probe);
    // One view for the whole (flat, orthographically seen) panel.
    const glm::dvec3 wo_l = ToLocal(wo, probe.x_s, probe.y_s, probe.n);
    const HoleRatios r = HolesTileRatios(model.params, *model.tile, wo_l);
    const glm::dvec3 transmittance = TransmittanceOfRatios(model.params, r);
    for (int j = 0; j < size; ++j) {
      for (int i = 0; i < size; ++i) {
        const glm::dvec2 p = PanelPoint(i, j, size);
        glm::dvec3 value(Checker(p));
        PanelHit hit;
        if (HitPanel(p, Radians(tilt_deg), &hit)) {
          glm::dvec3 wi;
          double irradiance = 0.0;
          LightAt(options.light * d, d * d, hit.point, &wi, &irradiance);
          const double cos_i = std::max(glm::dot(wi, hit.n), 0.0);
          value =
              value * transmittance + glm::dvec3(r.opaque * kHolesOpaqueAlbedo /
                                                 kPi * cos_i * irradiance);
        }
        image.At(panel * size + i, j) = value;
      }
    }
  }
  return image;
}

PreviewImage StackRows(const PreviewImage& top, const PreviewImage& bottom) {
  if (top.width != bottom.width || top.panel_size != bottom.panel_size) {
    throw InputError("cannot place renders of different layouts (" +
                     std::to_string(top.width) + " and " +
                     std::to_string(bottom.width) +
                     " pixels wide) side by side");
  }
  PreviewImage out = top;
  out.height += bottom.height;
  out.pixels.insert(out.pixels.end(), bottom.pixels.begin(),
                    bottom.pixels.end());
  auto append = [](auto* to, const auto& from) {
    to->insert(to->end(), from.begin(), from.end());
  };
  append(&out.panel_titles, bottom.panel_titles);
  append(&out.panel_warp_deg, bottom.panel_warp_deg);
  // One title per row: rows without one get an empty title.
  out.row_titles.resize(top.panel_size > 0 ? top.height / top.panel_size : 0);
  append(&out.row_titles, bottom.row_titles);
  return out;
}

double AutoExposure(const PreviewImage& image) {
  std::vector<double> peaks;
  peaks.reserve(image.pixels.size());
  for (const glm::dvec3& v : image.pixels) {
    peaks.push_back(std::max({v.x, v.y, v.z}));
  }
  if (peaks.empty()) return 1.0;
  const size_t k = std::min(peaks.size() - 1, peaks.size() * 99 / 100);
  std::nth_element(peaks.begin(), peaks.begin() + k, peaks.end());
  const double p99 = peaks[k];
  return p99 > 0.0 && std::isfinite(p99) ? 1.0 / p99 : 1.0;
}

void WritePreview(const PreviewImage& image, double exposure,
                  const std::string& exr_path, const std::string& png_path,
                  const std::vector<ExrAttribute>& attributes) {
  std::vector<float> linear;
  linear.reserve(image.pixels.size() * 3);
  for (const glm::dvec3& v : image.pixels) {
    for (int c = 0; c < 3; ++c) linear.push_back(static_cast<float>(v[c]));
  }
  const DisplayImage display = LabelledDisplay(image, exposure);
  WriteImage(exr_path, image.width, image.height, 3, false, true, linear,
             attributes);
  WriteImage(png_path, display.width, display.height, 3, false, false,
             display.rgb);
}

}  // namespace clothfit
