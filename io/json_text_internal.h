// Parsing JSON that comes from a file: a parameter file, a mip map's index or
// an EXR header's metadata. Internal to clothfit_io.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace clothfit {

// Deepest nesting of arrays and objects a clothfit JSON document may have.
// Clothfit's own files nest at most 4 levels (a Lafortune lookup table's
// rows); the limit bounds what a reader, printer or destructor recurses over.
inline constexpr int kMaxJsonDepth = 64;

// Parses `text` (named `name` in messages) strictly: RFC 8259 JSON, nested at
// most kMaxJsonDepth levels, and no key twice in one object (RFC 8259 leaves
// which duplicate wins to the reader; clothfit refuses to guess). Throws
// InputError "name: invalid JSON: ...", "name: key 'a.b[2].c' appears twice"
// or "name: JSON nested deeper than 64 levels (at 'a.b')".
// Json is nlohmann::json or nlohmann::ordered_json (keys kept in order).
template <typename Json>
Json ParseJsonText(const std::string& text, const std::string& name);

}  // namespace clothfit
