#include "export/gltf.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "export/png.h"
#include "io/atomic_file.h"
#include "io/input_error.h"
#include "io/text_util.h"

namespace clothfit {
namespace {

using json = nlohmann::ordered_json;

// glTF's enumerations (glTF 2.0 §5.1.2, §5.11.4).
constexpr int kFloat = 5126, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

template <typename T>
void Append(const std::vector<T>& values, std::vector<uint8_t>* bin) {
  const size_t start = bin->size();
  bin->resize(start + values.size() * sizeof(T));
  std::memcpy(bin->data() + start, values.data(), values.size() * sizeof(T));
  while (bin->size() % 4 != 0) bin->push_back(0);  // 4-byte alignment
}

json Rgb(const glm::dvec3& c) { return json::array({c.x, c.y, c.z}); }

}  // namespace

TriangleMesh ClothMesh(int n) {
  n = std::max(1, n);
  TriangleMesh mesh;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const double u = static_cast<double>(i) / n;
      const double v = static_cast<double>(j) / n;
      const double x = 2.0 * u - 1.0, y = 2.0 * v - 1.0;
      const double a = 1.5 * kPi;
      const double fold = 1.0 - 0.3 * y * y;
      const double z = 0.12 * std::cos(a * x) * fold;
      const double dzdx = -0.12 * a * std::sin(a * x) * fold;
      const double dzdy = 0.12 * std::cos(a * x) * (-0.6 * y);
      const glm::dvec3 normal = glm::normalize(glm::dvec3(-dzdx, -dzdy, 1.0));
      for (double p : {x, y, z})
        mesh.positions.push_back(static_cast<float>(p));
      for (int c = 0; c < 3; ++c) {
        mesh.normals.push_back(static_cast<float>(normal[c]));
      }
      mesh.uvs.push_back(static_cast<float>(u));
      mesh.uvs.push_back(static_cast<float>(1.0 - v));  // glTF: v down
    }
  }
  const uint32_t row = static_cast<uint32_t>(n) + 1;
  for (uint32_t j = 0; j < static_cast<uint32_t>(n); ++j) {
    for (uint32_t i = 0; i < static_cast<uint32_t>(n); ++i) {
      const uint32_t a = j * row + i, b = a + 1, c = a + row, d = c + 1;
      for (uint32_t k : {a, b, d, a, d, c}) mesh.indices.push_back(k);
    }
  }
  return mesh;
}

GltfTextures SheenTextures(const std::vector<SheenParams>& texels, int width,
                           int height, std::vector<SheenParams>* quantized) {
  std::vector<uint8_t> base, mr, sheen, sheen_rough;
  if (quantized) quantized->clear();
  for (const SheenParams& p : texels) {
    SheenParams q;
    for (int c = 0; c < 3; ++c) {
      base.push_back(SrgbByte(p.base_color[c]));
      sheen.push_back(SrgbByte(p.sheen_color[c]));
      q.base_color[c] = SrgbToLinear(base.back());
      q.sheen_color[c] = SrgbToLinear(sheen.back());
    }
    // Roughness in green, metallic 0 in blue; sheen roughness in alpha.
    // A roughness of 0 is outside the model (a delta lobe): 1/255 at least.
    const uint8_t r = std::max(LinearByte(p.roughness), uint8_t(1));
    const uint8_t rs = std::max(LinearByte(p.sheen_roughness), uint8_t(1));
    for (uint8_t v : {uint8_t(0), r, uint8_t(0)}) mr.push_back(v);
    for (uint8_t v : {uint8_t(0), uint8_t(0), uint8_t(0), rs}) {
      sheen_rough.push_back(v);
    }
    q.roughness = r / 255.0;
    q.sheen_roughness = rs / 255.0;
    if (quantized) quantized->push_back(q);
  }
  GltfTextures out;
  out.base_color = EncodePng(width, height, 3, base);
  out.metallic_roughness = EncodePng(width, height, 3, mr);
  out.sheen_color = EncodePng(width, height, 3, sheen);
  out.sheen_roughness = EncodePng(width, height, 4, sheen_rough);
  return out;
}

GltfDocument BuildGltf(const TriangleMesh& mesh, const GltfMaterial& material,
                       const std::string& bin_uri) {
  GltfDocument doc;
  json views = json::array(), accessors = json::array();
  auto add_view = [&](size_t offset, int target) {
    views.push_back({{"buffer", 0},
                     {"byteOffset", offset},
                     {"byteLength", doc.bin.size() - offset},
                     {"target", target}});
    return views.size() - 1;
  };
  const size_t vertices = mesh.Vertices();
  // POSITION needs min and max (glTF 2.0 §5.1.1).
  std::vector<float> lo(3, HUGE_VALF), hi(3, -HUGE_VALF);
  for (size_t k = 0; k < mesh.positions.size(); ++k) {
    lo[k % 3] = std::min(lo[k % 3], mesh.positions[k]);
    hi[k % 3] = std::max(hi[k % 3], mesh.positions[k]);
  }
  size_t offset = doc.bin.size();
  Append(mesh.positions, &doc.bin);
  accessors.push_back({{"bufferView", add_view(offset, kArrayBuffer)},
                       {"componentType", kFloat},
                       {"count", vertices},
                       {"type", "VEC3"},
                       {"min", lo},
                       {"max", hi}});
  offset = doc.bin.size();
  Append(mesh.normals, &doc.bin);
  accessors.push_back({{"bufferView", add_view(offset, kArrayBuffer)},
                       {"componentType", kFloat},
                       {"count", vertices},
                       {"type", "VEC3"}});
  offset = doc.bin.size();
  Append(mesh.uvs, &doc.bin);
  accessors.push_back({{"bufferView", add_view(offset, kArrayBuffer)},
                       {"componentType", kFloat},
                       {"count", vertices},
                       {"type", "VEC2"}});
  offset = doc.bin.size();
  Append(mesh.indices, &doc.bin);
  accessors.push_back({{"bufferView", add_view(offset, kElementArrayBuffer)},
                       {"componentType", kUnsignedInt},
                       {"count", mesh.indices.size()},
                       {"type", "SCALAR"}});
  // The textures' PNG files, in the buffer (images by bufferView).
  json images = json::array(), textures = json::array();
  auto add_texture = [&](const std::string& png) -> int {
    if (png.empty()) return -1;
    const size_t at = doc.bin.size();
    Append(std::vector<uint8_t>(png.begin(), png.end()), &doc.bin);
    views.push_back(
        {{"buffer", 0}, {"byteOffset", at}, {"byteLength", png.size()}});
    images.push_back(
        {{"bufferView", views.size() - 1}, {"mimeType", "image/png"}});
    textures.push_back({{"sampler", 0}, {"source", images.size() - 1}});
    return static_cast<int>(textures.size()) - 1;
  };
  const GltfTextures& tx = material.textures;
  const int base_texture = add_texture(tx.base_color);
  const int mr_texture = add_texture(tx.metallic_roughness);
  const int sheen_texture = add_texture(tx.sheen_color);
  const int sheen_rough_texture = add_texture(tx.sheen_roughness);
  const SheenParams& s = material.sheen;
  json buffer = {{"byteLength", doc.bin.size()}};
  if (!bin_uri.empty()) buffer["uri"] = bin_uri;
  json m = {{"name", material.name},
            {"pbrMetallicRoughness",
             {{"baseColorFactor",
               {s.base_color.x, s.base_color.y, s.base_color.z, 1.0}},
              {"metallicFactor", 0.0},
              {"roughnessFactor", s.roughness}}},
            {"extensions",
             {{"KHR_materials_sheen",
               {{"sheenColorFactor", Rgb(s.sheen_color)},
                {"sheenRoughnessFactor", s.sheen_roughness}}}}},
            {"extras", json::parse(material.extras_json)}};
  auto info = [](int index) { return json{{"index", index}, {"texCoord", 0}}; };
  if (base_texture >= 0) {
    m["pbrMetallicRoughness"]["baseColorTexture"] = info(base_texture);
  }
  if (mr_texture >= 0) {
    m["pbrMetallicRoughness"]["metallicRoughnessTexture"] = info(mr_texture);
  }
  json& sheen_ext = m["extensions"]["KHR_materials_sheen"];
  if (sheen_texture >= 0) sheen_ext["sheenColorTexture"] = info(sheen_texture);
  if (sheen_rough_texture >= 0) {
    sheen_ext["sheenRoughnessTexture"] = info(sheen_rough_texture);
  }
  json gltf = {
      {"asset", {{"version", "2.0"}, {"generator", "clothfit export"}}},
      {"extensionsUsed", {"KHR_materials_sheen"}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"name", material.name}, {"mesh", 0}}}},
      {"meshes",
       {{{"name", material.name},
         {"primitives",
          {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}},
            {"indices", 3},
            {"material", 0}}}}}}},
      {"materials", {m}},
      {"buffers", {buffer}},
      {"bufferViews", views},
      {"accessors", accessors}};
  if (!textures.empty()) {
    // Linear filtering with mipmaps, clamped at the edges (a fitted map
    // need not tile; api/material.h filters alike).
    gltf["samplers"] = {{{"magFilter", 9729},
                         {"minFilter", 9987},
                         {"wrapS", 33071},
                         {"wrapT", 33071}}};
    gltf["images"] = images;
    gltf["textures"] = textures;
  }
  doc.json = gltf.dump(1);
  return doc;
}

std::vector<uint8_t> GlbBytes(const GltfDocument& document) {
  std::string text = document.json;
  while (text.size() % 4 != 0) text.push_back(' ');
  std::vector<uint8_t> bin = document.bin;
  while (bin.size() % 4 != 0) bin.push_back(0);
  std::vector<uint8_t> out;
  auto u32 = [&](uint32_t v) {
    for (int k = 0; k < 4; ++k)
      out.push_back(static_cast<uint8_t>(v >> (8 * k)));
  };
  const uint32_t length = 12 + 8 + text.size() + 8 + bin.size();
  u32(0x46546C67);  // "glTF"
  u32(2);
  u32(length);
  u32(static_cast<uint32_t>(text.size()));
  u32(0x4E4F534A);  // "JSON"
  out.insert(out.end(), text.begin(), text.end());
  u32(static_cast<uint32_t>(bin.size()));
  u32(0x004E4942);  // "BIN\0"
  out.insert(out.end(), bin.begin(), bin.end());
  return out;
}

std::vector<std::string> WriteGltf(const TriangleMesh& mesh,
                                   const GltfMaterial& material,
                                   const std::string& path) {
  if (text_util::HasExtension(path, ".glb")) {
    const std::vector<uint8_t> bytes = GlbBytes(BuildGltf(mesh, material, ""));
    WriteFileAtomically(path, std::string(bytes.begin(), bytes.end()));
    return {path};
  }
  if (!text_util::HasExtension(path, ".gltf")) {
    throw InputError(path + ": a glTF export ends in .gltf or .glb");
  }
  const std::filesystem::path p(path);
  const std::string bin_name = p.stem().string() + ".bin";
  const std::string bin_path = (p.parent_path() / bin_name).string();
  const GltfDocument doc = BuildGltf(mesh, material, bin_name);
  // The buffer first: a .gltf is never left naming a missing .bin.
  WriteFileAtomically(bin_path, std::string(doc.bin.begin(), doc.bin.end()));
  WriteFileAtomically(path, doc.json + "\n");
  return {path, bin_path};
}

}  // namespace clothfit
