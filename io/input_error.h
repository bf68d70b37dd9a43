// Errors in user input (measurement tables, parameter files, command lines).
//
// Every reader throws InputError with a message that names the file, the
// line/column or key, and the problem; apps/ turns it into exit status 2.
#pragma once

#include <stdexcept>
#include <string>

namespace clothfit {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message)
      : std::runtime_error(message) {}
};

// "file:line:column: problem" (line/column 1-based; 0 omits them).
std::string FormatLocation(const std::string& file, int line, int column);

}  // namespace clothfit
