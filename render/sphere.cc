#include "render/sphere.h"

#include <cmath>

namespace clothfit {

PreviewImage RenderSphere(const ModelParams& params, const glm::dvec3& light,
                          double irradiance, int size) {
  PreviewImage image;
  image.width = image.height = size;
  image.pixels.assign(static_cast<size_t>(size) * size, glm::dvec3(0.0));
  image.panel_titles = {"sphere"};
  const glm::dvec3 l = glm::normalize(light), v(0.0, 0.0, 1.0);
  for (int j = 0; j < size; ++j) {
    for (int i = 0; i < size; ++i) {
      const double x = (i + 0.5) * 2.0 / size - 1.0;
      const double y = 1.0 - (j + 0.5) * 2.0 / size;
      const double r2 = x * x + y * y;
      if (r2 >= 1.0) continue;
      const TexelFrame frame =
          MakeTexelFrame(glm::dvec3(x, y, std::sqrt(1.0 - r2)));
      const glm::dvec3 wi = ToTexelFrame(frame, l);
      const glm::dvec3 wo = ToTexelFrame(frame, v);
      if (!(wi.z > 0.0)) continue;
      image.At(i, j) =
          Evaluate(params, wi, wo, Quantity::kBrdf) * (wi.z * irradiance);
    }
  }
  return image;
}

}  // namespace clothfit
