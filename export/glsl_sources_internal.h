// The texts of export/glsl/*.glsl, compiled in (glsl_sources.cc.in).
#pragma once

namespace clothfit {
namespace glsl_sources {

extern const char* const kCommon;
extern const char* const kThread;
extern const char* const kCloth;
extern const char* const kLafortune;
extern const char* const kSlab;
extern const char* const kHoles;
extern const char* const kLafortuneMap;
extern const char* const kEnergyBound;

}  // namespace glsl_sources
}  // namespace clothfit
