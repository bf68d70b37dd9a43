#include <set>
#include <string>
#include <vector>

#include "io/input_error.h"
#include "io/json_text_internal.h"
#include "io/text_util.h"

namespace clothfit {
namespace {

// One open array or object while parsing, for the path in messages and the
// duplicate-key check.
struct Open {
  bool object = false;
  std::set<std::string> keys;  // object: the keys seen so far
  std::string key;             // object: the key being read
  long long index = -1;        // array: the element being read
};

std::string PathOf(const std::vector<Open>& open) {
  std::string path;
  for (const Open& o : open) {
    if (o.object) {
      if (o.key.empty() && o.keys.empty()) continue;
      path += (path.empty() ? "" : ".") + o.key;
    } else if (o.index >= 0) {
      path += "[" + std::to_string(o.index) + "]";
    }
  }
  return text_util::Printable(path);
}

// A value (scalar, array or object) starts inside the innermost open array.
void CountElement(std::vector<Open>* open) {
  if (!open->empty() && !open->back().object) ++open->back().index;
}

}  // namespace

template <typename Json>
Json ParseJsonText(const std::string& text, const std::string& name) {
  std::vector<Open> open;
  using Event = nlohmann::json::parse_event_t;
  const typename Json::parser_callback_t check = [&](int /*depth*/, Event event,
                                                     Json& parsed) {
    switch (event) {
      case Event::object_start:
      case Event::array_start: {
        CountElement(&open);
        if (static_cast<int>(open.size()) >= kMaxJsonDepth) {
          throw InputError(name + ": JSON nested deeper than " +
                           std::to_string(kMaxJsonDepth) + " levels (at '" +
                           PathOf(open).substr(0, 60) + "...')");
        }
        Open o;
        o.object = event == Event::object_start;
        open.push_back(std::move(o));
        break;
      }
      case Event::key: {
        Open& o = open.back();
        o.key = parsed.template get<std::string>();
        if (!o.keys.insert(o.key).second) {
          throw InputError(name + ": key '" + PathOf(open) +
                           "' appears twice (each key may appear once)");
        }
        break;
      }
      case Event::object_end:
      case Event::array_end:
        open.pop_back();
        break;
      case Event::value:
        CountElement(&open);
        break;
    }
    return true;
  };
  try {
    return Json::parse(text, check);
  } catch (const nlohmann::json::exception& e) {
    // A parse error's message carries "at line L, column C" and the bytes
    // last read (escaped: they may not be UTF-8); a number too large for a
    // double is an out_of_range error (406) without a position.
    std::string what = text_util::Printable(e.what());
    const size_t pos = what.find("parse error");
    const size_t bracket = what.find("] ");
    if (pos != std::string::npos) {
      what = what.substr(pos);
    } else if (bracket != std::string::npos) {
      what = what.substr(bracket + 2);
    }
    throw InputError(name + ": invalid JSON: " + what);
  }
}

template nlohmann::json ParseJsonText<nlohmann::json>(const std::string&,
                                                      const std::string&);
template nlohmann::ordered_json ParseJsonText<nlohmann::ordered_json>(
    const std::string&, const std::string&);

}  // namespace clothfit
