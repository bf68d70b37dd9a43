#include "io/text_util.h"

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace clothfit {
namespace text_util {

bool IsSpace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' ||
         c == '\f';
}

std::string_view Trim(std::string_view text) {
  while (!text.empty() && IsSpace(text.front())) text.remove_prefix(1);
  while (!text.empty() && IsSpace(text.back())) text.remove_suffix(1);
  return text;
}

std::string Lower(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return lower;
}

std::string EscapeControl(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      char escaped[5];
      std::snprintf(escaped, sizeof(escaped), "\\x%02x", u);
      out += escaped;
    } else {
      out += c;
    }
  }
  return out;
}

std::string Printable(std::string_view text) {
  std::string out;
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c >= 0x20 && c < 0x7f && c != '\\') {
      out += ch;
    } else {
      char escaped[8];
      std::snprintf(escaped, sizeof(escaped), "\\x%02x", c);
      out += escaped;
    }
  }
  return out;
}

std::string Quote(std::string_view text) {
  std::string quoted = Printable(text.substr(0, kMaxQuotedLength));
  // A quote inside the field is escaped like any other odd byte.
  for (size_t pos = quoted.find('\''); pos != std::string::npos;
       pos = quoted.find('\'', pos + 4)) {
    quoted.replace(pos, 1, "\\x27");
  }
  if (text.size() > kMaxQuotedLength) quoted += "...";
  return "'" + quoted + "'";
}

std::optional<std::string> FormatVersion(std::string_view comment,
                                         std::string_view magic) {
  const std::string_view words = Trim(comment);
  if (Lower(words.substr(0, magic.size())) != magic ||
      (words.size() > magic.size() && !IsSpace(words[magic.size()]))) {
    return std::nullopt;
  }
  return std::string(Trim(words.substr(magic.size())));
}

bool EndsWith(std::string_view text, std::string_view suffix) {
  return text.size() >= suffix.size() &&
         text.substr(text.size() - suffix.size()) == suffix;
}

bool HasExtension(std::string_view path, std::string_view extension) {
  return path.size() >= extension.size() &&
         Lower(path.substr(path.size() - extension.size())) == Lower(extension);
}

std::vector<std::string_view> SplitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      fields.push_back(line.substr(start));
      return fields;
    }
    fields.push_back(line.substr(start, comma - start));
    start = comma + 1;
  }
}

std::string FormatNumber(double value, int significant) {
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.*g", significant, value);
  return buffer;
}

std::string OneLine(std::string_view text) {
  std::string line(text);
  for (char& c : line) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return line;
}

}  // namespace text_util
}  // namespace clothfit
