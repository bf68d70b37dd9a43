#include "io/input_error.h"

#include <string>

namespace clothfit {

std::string FormatLocation(const std::string& file, int line, int column) {
  std::string location = file;
  if (line > 0) {
    location += ':' + std::to_string(line);
    if (column > 0) location += ':' + std::to_string(column);
  }
  return location;
}

}  // namespace clothfit
