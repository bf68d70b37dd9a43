// clothfit is two executables. `clothfit` reads and writes tables, parameter
// files and parameter mip maps, and loads no image library (OpenImageIO and
// OpenCV bring some 260 shared libraries, ~0.15 s, to every start);
// `clothfit-full`, installed beside it, has every command. `clothfit` runs
// `clothfit-full` with its own arguments for what needs images: plot, report,
// render, bench, holes, `fit --stack`, `fit --model holes`, `synth --stack`,
// `synth --model slab --error-map`, and a holes parameter file.
#pragma once

namespace clothfit {

// The arguments main() was given, for RunInFullBinary.
void SetProgramArguments(int argc, char** argv);

// Replaces this process with clothfit-full (the same arguments); throws
// InputError when it cannot be run. Only the light executable calls it.
[[noreturn]] void RunInFullBinary();

}  // namespace clothfit
