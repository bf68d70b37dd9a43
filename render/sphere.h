// A sphere under one directional light, the scene real-time renderers'
// material previews use (three.js, the Khronos sample viewer), in linear
// radiance: what the browser test of the glTF export (tests/
// browser_render_test.cc) compares three.js' image with.
//
// An orthographic camera looks down -z at a sphere of radius 1 that fills
// the image's [-1, 1]^2 (pixel (i, j) at x = (i + 0.5) 2 / size - 1, y = 1
// - (j + 0.5) 2 / size, row 0 at the top); the surface point's normal is n
// = (x, y, sqrt(1 - x^2 - y^2)), its frame models/lafortune.h
// MakeTexelFrame(n) (isotropic models do not depend on it), the view +z.
// Radiance = f(wi, wo) max(wi.z, 0) E for a light of irradiance E (at
// normal incidence) from direction `light`; 0 off the sphere.
#pragma once

#include "models/evaluate.h"
#include "render/preview.h"

namespace clothfit {

PreviewImage RenderSphere(const ModelParams& params, const glm::dvec3& light,
                          double irradiance, int size);

}  // namespace clothfit
