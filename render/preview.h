// Preview renders of fitted cloth (`clothfit render`): small
// images, computed in linear radiance, that show a parameter set the way
// the paper's Fig. 12 does.
//
// Scene (all panels): an orthographic camera looking down -z (every view
// direction is +z in the world), a point light of intensity d^2 at
// distance d in direction `light` (so the irradiance is about 1 at the
// origin), and no other light. A panel spans [-1.2, 1.2]^2 of the world's
// x, y; its pixel (i, j) has row j = 0 at the top.
//  - Cylinders (thread, cloth, lafortune, Lafortune mip map): radius 1,
//    axis +y, wrapped in the cloth with its warp (+x of the surface frame)
//    along the axis (threads vertical), around it (horizontal) and at 45
//    degrees (diagonal): three panels. Radiance = rho(wi, wo) I / r^2. The
//    surface's texture coordinates (u, v) are world lengths along the warp
//    and the weft, measured from the point (0, 0, 1): the axis coordinate y
//    and the arc length asin(x) around the axis, turned with the warp.
//  - Slab: a square panel (half-size 0.8) tilted by `tilt_deg` about +y over
//    a checker backdrop (unlit, values kCheckerDark/kCheckerLight); the
//    light in front of the panel (front-lit: reflection) and mirrored
//    behind it (back-lit: transmission), two panels; the backdrop is seen
//    through the slab attenuated by its direct transmittance D(|wo.z|).
//  - Holes: the same panel at three tilts (0, tilt, 2 tilt; front-lit),
//    whose transmittance T(wo) (per channel) lets the backdrop through and
//    whose opaque fraction is a grey diffuse surface (albedo
//    kHolesOpaqueAlbedo).
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "api/material.h"
#include "models/evaluate.h"
#include "models/holes_tile.h"

namespace clothfit {

inline constexpr double kCheckerDark = 0.1, kCheckerLight = 0.5;
inline constexpr double kHolesOpaqueAlbedo = 0.6;
inline constexpr double kPanelExtent = 1.2;  // world half-width of a panel

struct PreviewOptions {
  int size = 192;                                  // pixels per panel side
  glm::dvec3 light{0.5, 0.5, 0.7071067811865476};  // unit, towards the light
  double light_distance = 6.0;                     // world units
  double tilt_deg = 35.0;                          // slab and holes panels
  double tile = 0.8;  // world size of one repeat of a texture (MipmapRho)
};

// Linear radiance, row-major, row 0 at the top: one or more rows
// (StackRows) of square panels of panel_size pixels.
struct PreviewImage {
  int width = 0, height = 0, panel_size = 0;
  std::vector<glm::dvec3> pixels;
  // Per panel, row by row, left to right: its title (e.g. "warp
  // vertical") and, for a cylinder, the warp's angle from the cylinder's
  // axis in degrees (0: vertical on screen, 90: horizontal; NaN for
  // panels that are not cylinders).
  std::vector<std::string> panel_titles;
  std::vector<double> panel_warp_deg;
  // Per row of panels, top to bottom: what it shows (e.g. "fit: P.json");
  // may be empty.
  std::vector<std::string> row_titles;
  glm::dvec3& At(int x, int y) { return pixels[size_t(y) * width + x]; }
  const glm::dvec3& At(int x, int y) const {
    return pixels[size_t(y) * width + x];
  }
};

// The world position of the centre of pixel (i, j) of a panel (z = 0).
glm::dvec2 PanelPoint(int i, int j, int size);

// rho(wi, wo) of a surface point: wi and wo in the surface frame, `uv` the
// point's texture coordinates (world units along the warp and the weft) and
// `footprint` the width of the pixel's footprint on the surface (world
// units; the larger side, so grazing pixels cover more).
using SurfaceRho =
    std::function<glm::dvec3(const glm::dvec3& wi, const glm::dvec3& wo,
                             const glm::dvec2& uv, double footprint)>;

// Thread, cloth or lafortune: the three cylinders. Requires a model that
// reflects (not a slab).
PreviewImage RenderCylinders(const ModelParams& params,
                             const PreviewOptions& options);
// The three cylinders of a spatially varying surface.
PreviewImage RenderCylinders(const SurfaceRho& rho,
                             const PreviewOptions& options);

// The level of a mip map with a `base_width`-texel level 0 stretched over
// `tile` world units whose texels are nearest in size to `footprint`:
// round(log2(footprint base_width / tile)), clamped to [0, levels - 1]
// (nearest-level, nearest-texel look-up, as Material::Rho does texels).
int MipLevelForFootprint(double footprint, double tile, int base_width,
                         int levels);

// A Lafortune parameter mip map (Material::Load of an .exr) repeated every
// `tile` world units along u and v: (s, t) = (frac(u / tile),
// frac(v / tile)) at MipLevelForFootprint's level. The material is copied.
SurfaceRho MipmapRho(const Material& material, double tile);
// Front-lit and back-lit panels.
PreviewImage RenderSlab(const SlabParams& params,
                        const PreviewOptions& options);
// A holed layer (its tile required: holes/hole_texture.h LoadHolesModel)
// on panels at three tilts over a checker.
PreviewImage RenderHoles(const HolesModel& model,
                         const PreviewOptions& options);

// `top` above `bottom` (same width and panel size; the titles follow).
// Throws InputError otherwise.
PreviewImage StackRows(const PreviewImage& top, const PreviewImage& bottom);

// The exposure that maps the 99th percentile of the pixels' largest channel
// to 1 (1 for a black image).
double AutoExposure(const PreviewImage& image);

// The height of the label band above each row of panels in the PNG.
inline constexpr int kLabelBand = 44;

// The tone-mapped image (exposure, clamp to [0, 1], sRGB transfer curve)
// with a white band of kLabelBand pixels above each row of panels: the
// row's title, each panel's title and, for a cylinder, a double-headed
// arrow along its warp (render/preview_labels.cc). Interleaved RGB in
// [0, 1], width x (height + rows kLabelBand).
struct DisplayImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
};
DisplayImage LabelledDisplay(const PreviewImage& image, double exposure);

// A string attribute of the EXR's header (name, value).
using ExrAttribute = std::pair<std::string, std::string>;

// Writes the linear image as OpenEXR (float RGB, no labels; `attributes` in
// its header) and LabelledDisplay as 8-bit PNG; both atomically. Throws
// InputError naming the path.
void WritePreview(const PreviewImage& image, double exposure,
                  const std::string& exr_path, const std::string& png_path,
                  const std::vector<ExrAttribute>& attributes = {});

}  // namespace clothfit
