// Image stacks: one image per (light, view) direction pair, listed in a CSV
// manifest, read with OpenImageIO (EXR, PNG, TIFF, ...). Each pixel (s, t)
// of image k becomes one table row (directions of k, value = the pixel's
// r,g,b, or its single channel), so a stack becomes a spatially varying
// measurement table (s = column, t = row of the pixel).
//
// Manifest (docs/formats.md conventions: '#' metadata lines, then a header; any
// column order, case-insensitive names; angles in degrees unless
// "# units: radians"; image paths relative to the manifest's folder):
//   # clothfit-stack 1
//   # quantity: cosine_weighted
//   theta_i,phi_i,theta_o,phi_o,file
//   30,0,45,180,img_000.exr
// The image's alpha channel, when present, is the per-view coverage: it is
// stored in TableRow::alpha (1 without alpha).
// Per-texel normals (Daubert et al. 2001, Section 3: the frame of a
// spatially varying fit) come from a normal map named by a metadata line
//   # normal_map: normals.exr
// an image of the stack's size whose three colour channels hold each
// pixel's normal (x, y, z) in the surface frame: as stored in a float image
// (EXR, TIFF), as 2 v - 1 in an integer one (PNG; v in [0, 1]); normalised
// on read, zero or non-finite normals are an error; alpha is ignored. The
// table then has has_normal set.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "io/table.h"

namespace clothfit {

// A block of pixels: columns [x, x + width), rows [y, y + height); a
// width of 0 stands for the whole image.
struct PixelRegion {
  int x = 0, y = 0, width = 0, height = 0;
};

struct ReadStackOptions {
  // Keep only every `stride`-th pixel in x and y (1 = all).
  int stride = 1;
  // If set: receives the path of every image read (the normal map too), so
  // that a caller can refuse an output that would replace one.
  std::vector<std::string>* images = nullptr;
  // Only these pixels of each image (and of the normal map), read as a
  // region (tiled files: the tiles it touches; scanline files, PNG: its
  // rows, decoded whole); s, t then count from the region's corner. A
  // region not inside the images is an InputError naming the image.
  PixelRegion region;
};

// Throws InputError naming the manifest (line, column) or the image file
// and the problem: missing column, bad number, missing/unreadable/truncated
// image, images of different sizes, empty manifest.
MeasurementTable ReadImageStack(const std::string& manifest_path,
                                const ReadStackOptions& options = {});

// A stack read an image and a region at a time: the rows ReadImageStack
// makes, in its order (image by image, row by row), without holding more
// than the region asked for. Throws as ReadImageStack.
class ImageStackReader {
 public:
  // Parses the manifest and reads the size of its first image (the normal
  // map's when there is one).
  explicit ImageStackReader(const std::string& manifest_path);
  ~ImageStackReader();
  ImageStackReader(const ImageStackReader&) = delete;
  ImageStackReader& operator=(const ImageStackReader&) = delete;

  // The table without rows (source, metadata, quantity, has_texels,
  // has_normal), and one row per image with its directions (wi, wo,
  // source_line; value 0): the order of the images.
  const MeasurementTable& header() const;
  const MeasurementTable& directions() const;
  size_t images() const;
  int width() const;   // of every image
  int height() const;  // of every image
  // The path of image k as resolved from the manifest's folder, and of the
  // normal map ("" when none).
  std::string ImagePath(size_t k) const;
  std::string NormalMapPath() const;

  // Appends to table->rows the rows of image k's pixels in `region` (row
  // by row, every `stride`-th pixel; s, t from the region's corner when
  // `local`, else of the image), and sets table->channels to 3 and
  // table->has_alpha when the image has colour or alpha.
  void AppendRows(size_t k, const PixelRegion& region, int stride, bool local,
                  MeasurementTable* table);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// Writes a stack from a spatially varying table whose rows cover a full
// width x height grid of (s, t) for each distinct (wi, wo) pair: one
// image per pair (format from `extension`, e.g. ".exr" or ".png"; alpha
// written when `with_alpha`), with has_normal a normal map (STEM_normal.EXT;
// every pair's rows of a texel must hold the same normal), and the
// manifest. Atomic per file.
void WriteImageStack(const MeasurementTable& table,
                     const std::string& manifest_path,
                     const std::string& extension, bool with_alpha);

// Writes one image atomically, its format from the path's extension:
// `colour_channels` (1 or 3) plus alpha when `with_alpha`, pixels
// interleaved row by row (row 0 at the top); float_pixels: stored as FLOAT
// (EXR, TIFF), else as 8 bit (PNG; values in [0, 1]). Throws InputError
// naming the path. `attributes`: string attributes (name, value) of the
// file's header (OpenEXR: Imf::StringAttribute; e.g. "clothfit:command").
void WriteImage(
    const std::string& path, int width, int height, int colour_channels,
    bool with_alpha, bool float_pixels, const std::vector<float>& pixels,
    const std::vector<std::pair<std::string, std::string>>& attributes = {});

}  // namespace clothfit
