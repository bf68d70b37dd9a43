// glTF 2.0 files (Khronos glTF 2.0 specification) of a cloth: a draped
// sheet with a material of the glTF metallic-roughness model under
// KHR_materials_sheen (models/sheen.h), as a .gltf with its .bin beside it
// or as one binary .glb. The material's "extras" hold what the caller
// wants said about it (the conversion's error, the source).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "models/sheen.h"

namespace clothfit {

// An indexed triangle mesh: positions and unit normals (x, y, z), texture
// coordinates (u, v), counter-clockwise triangles.
struct TriangleMesh {
  std::vector<float> positions, normals, uvs;
  std::vector<uint32_t> indices;
  size_t Vertices() const { return positions.size() / 3; }
};

// A square sheet of side 2 (metres) in the x-y plane, +z up, draped in two
// soft folds along y: z = 0.12 cos(1.5 pi x) (1 - 0.3 y^2), on an n x n
// grid of quads (n >= 1), normals from the surface's derivatives; u along
// x (the warp, docs/formats.md), v along y (the weft).
TriangleMesh ClothMesh(int n = 48);

// A texture map's textures as PNG files (export/png.h; empty: none):
// base colour and sheen colour sRGB-encoded; roughness in the green channel
// of the metallic-roughness texture (blue, metallic, 0) and sheen
// roughness in the alpha channel of its texture, linear (glTF 2.0 §3.9,
// KHR_materials_sheen). The material's factors multiply them.
struct GltfTextures {
  std::string base_color, metallic_roughness, sheen_color, sheen_roughness;
};

// The four textures of a width x height map of materials (row 0 first),
// and in *quantized (may be null) the materials the 8-bit textures give
// back (with factors 1).
GltfTextures SheenTextures(const std::vector<SheenParams>& texels, int width,
                           int height, std::vector<SheenParams>* quantized);

struct GltfMaterial {
  std::string name = "cloth";
  SheenParams sheen;
  GltfTextures textures;
  std::string extras_json = "{}";  // a JSON object: the material's extras
};

// The glTF document and its binary buffer. `bin_uri`: the .bin's file name
// for a .gltf; empty for a .glb (the buffer is its BIN chunk).
struct GltfDocument {
  std::string json;
  std::vector<uint8_t> bin;
};
GltfDocument BuildGltf(const TriangleMesh& mesh, const GltfMaterial& material,
                       const std::string& bin_uri);

// The .glb container of a document (glTF 2.0 §4.4: 12-byte header, a JSON
// chunk padded with spaces and a BIN chunk padded with zeros to 4 bytes).
std::vector<uint8_t> GlbBytes(const GltfDocument& document);

// Writes `path`: a ".glb" as one file; a ".gltf" with its buffer in
// `path` without the extension + ".bin" beside it. Each file is replaced
// atomically (io/atomic_file.h). Throws InputError for another extension
// and when a file cannot be written. Returns the files written.
std::vector<std::string> WriteGltf(const TriangleMesh& mesh,
                                   const GltfMaterial& material,
                                   const std::string& path);

}  // namespace clothfit
