// A block of a Lafortune texel map fitted alone (clothfit fit --region) as
// a part file, and parts assembled into the texture (clothfit merge;
// docs/scale.md). A part is the block's parameter mip map
// (io/param_mipmap.h, ToParamMipmap) whose index, in the EXR header,
// records under metadata.part the block, the texture's size, the stack and
// the fit's options, what each texel's fit came to, and the models of the
// block's last level in full precision (they start the fits of the levels
// above the blocks, fitting/lafortune_merge.h).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "fitting/lafortune_mip.h"
#include "io/param_mipmap.h"

namespace clothfit {

struct LafortunePartInfo {
  int x = 0, y = 0, width = 0, height = 0;  // the block, in texels
  int texture_width = 0, texture_height = 0;
  bool mip = true;
  std::string stack;             // the image-stack manifest (absolute)
  std::vector<std::string> fit;  // the fit's options, as given
};

// "" when a block x, y, width, height can be a part of a texture of
// texture_width x texture_height: width and height powers of two that
// divide the texture's, x and y multiples of them; else the problem.
std::string LafortuneRegionProblem(int x, int y, int width, int height,
                                   int texture_width, int texture_height);

// The levels of a block's fit that are the texture's levels restricted to
// the block: 0 .. log2(min(width, height)) with mip (a texel of a level
// further down spans blocks), else level 0.
size_t LafortunePartLevels(const LafortunePartInfo& info);

// The part file's mip map of a block's fit (levels of the block's own
// pyramid; those past LafortunePartLevels are kept but not merged).
ParamMipmap ToPartMipmap(const LafortuneMipResult& block,
                         const LafortunePartInfo& info);

struct LafortunePart {
  std::string path;
  LafortunePartInfo info;
  ParamMipmap map;
  // Levels 0 .. LafortunePartLevels - 1 of the block: each texel's report
  // as the fit wrote it and its lobe count; models in full at the last.
  LafortuneMipResult result;
};

// Throws InputError naming the file for a file that is not a part.
LafortunePart ReadLafortunePart(const std::string& path);

// The texture's levels 0 .. LafortunePartLevels - 1 from parts that tile
// it exactly once. InputError naming a missing block (as x,y,w,h), an
// overlapping one (and both parts), or a part of another texture, stack,
// fit or block size.
LafortuneMipResult AssembleLafortuneParts(
    const std::vector<LafortunePart>& parts);

// ToParamMipmap of a merged result whose levels below the parts' are those
// of AssembleLafortuneParts: those levels' channels copied from the parts
// as they are (the values the block fits wrote), the levels above from
// the result.
ParamMipmap MergedParamMipmap(const LafortuneMipResult& merged,
                              const std::vector<LafortunePart>& parts);

}  // namespace clothfit
