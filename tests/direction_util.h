// Directions, presets and example materials as the model tests write them.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "models/lafortune.h"
#include "models/math.h"
#include "models/presets.h"
#include "models/sheen.h"

namespace clothfit {
namespace testing_util {

// The unit vector at polar angle theta and azimuth phi (degrees) in the
// surface frame (docs/formats.md).
inline glm::dvec3 Dir(double theta_deg, double phi_deg) {
  const double t = Radians(theta_deg), p = Radians(phi_deg);
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

// A cloth preset by name (a test failure when there is none).
inline ClothParams Preset(const std::string& name) {
  ClothParams c;
  EXPECT_TRUE(GetPreset(name, &c)) << name;
  return c;
}

// A glTF cloth material with every part visible: a coloured base of medium
// roughness under a bright, fairly smooth sheen.
inline SheenParams Velvety() {
  SheenParams p;
  p.base_color = glm::dvec3(0.3, 0.2, 0.1);
  p.roughness = 0.6;
  p.sheen_color = glm::dvec3(0.7, 0.5, 0.4);
  p.sheen_roughness = 0.35;
  return p;
}

// Two lobes (a forward lobe, anisotropic, and a retro-reflective one) that
// differ per channel, on a tilted texel.
inline LafortuneModel TiltedLafortune() {
  LafortuneModel m;
  m.normal = glm::normalize(glm::dvec3(0.2, -0.1, 1.0));
  m.params.diffuse = glm::dvec3(0.05, 0.08, 0.1);
  LafortuneLobe forward;
  forward.cx = glm::dvec3(-0.9, -0.85, -0.8);
  forward.cy = glm::dvec3(-0.6, -0.6, -0.5);
  forward.cz = glm::dvec3(0.8, 0.75, 0.7);
  forward.n = glm::dvec3(20.0, 18.0, 16.0);
  LafortuneLobe retro;
  retro.cx = retro.cy = glm::dvec3(0.6);
  retro.cz = glm::dvec3(0.5);
  retro.n = glm::dvec3(4.0);
  m.params.lobes = {forward, retro};
  return m;
}

}  // namespace testing_util
}  // namespace clothfit
