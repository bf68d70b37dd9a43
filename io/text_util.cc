#include "io/text_util.h"

#include <algorithm>
#include <charconv>
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

std::vector<std::string_view> SplitFields(std::string_view line,
                                          char separator) {
  std::vector<std::string_view> fields;
  const bool quotes = line.find('"') != std::string_view::npos;
  size_t start = 0;
  while (true) {
    size_t end = line.find(separator, start);
    if (quotes) {
      // A quoted field: from its opening quote (after spaces) to the
      // closing one that is not doubled.
      size_t open = start;
      while (open < line.size() && (line[open] == ' ' || line[open] == '\t') &&
             line[open] != separator) {
        ++open;
      }
      if (open < line.size() && line[open] == '"') {
        size_t close = open + 1;
        while (close < line.size()) {
          if (line[close] == '"') {
            if (close + 1 < line.size() && line[close + 1] == '"') {
              close += 2;
              continue;
            }
            break;
          }
          ++close;
        }
        if (close < line.size()) {
          end = line.find(separator, close);
          const std::string_view rest = line.substr(
              close + 1,
              (end == std::string_view::npos ? line.size() : end) - close - 1);
          // Text after the closing quote other than spaces keeps the
          // field as written (the number reader then names it).
          if (Trim(rest).empty()) {
            fields.push_back(line.substr(open + 1, close - open - 1));
            if (end == std::string_view::npos) return fields;
            start = end + 1;
            continue;
          }
        }
      }
    }
    if (end == std::string_view::npos) {
      fields.push_back(line.substr(start));
      return fields;
    }
    fields.push_back(line.substr(start, end - start));
    start = end + 1;
  }
}

std::string FormatNumber(double value) {
  char buffer[40];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

std::string FormatNumber(double value, int significant) {
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.*g", significant, value);
  return buffer;
}

namespace {

// Optimal string alignment distance (Damerau-Levenshtein with each
// transposition counted once), case-insensitive.
size_t EditDistance(std::string_view a, std::string_view b) {
  const std::string x = Lower(a), y = Lower(b);
  std::vector<std::vector<size_t>> d(x.size() + 1,
                                     std::vector<size_t>(y.size() + 1));
  for (size_t i = 0; i <= x.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= y.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= x.size(); ++i) {
    for (size_t j = 1; j <= y.size(); ++j) {
      const size_t cost = x[i - 1] == y[j - 1] ? 0 : 1;
      d[i][j] =
          std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && x[i - 1] == y[j - 2] && x[i - 2] == y[j - 1]) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[x.size()][y.size()];
}

}  // namespace

std::string DidYouMean(std::string_view given,
                       const std::vector<std::string>& candidates,
                       std::string_view prefix) {
  if (given.empty() || given.size() > 64) return "";
  const std::string lower = Lower(given);
  const std::string* best = nullptr;
  size_t best_distance = std::max<size_t>(1, given.size() / 3) + 1;
  const std::string* extends = nullptr;  // the one candidate given starts
  int extending = 0;
  for (const std::string& candidate : candidates) {
    const std::string name = Lower(candidate);
    if (name == lower) continue;
    if (name.rfind(lower, 0) == 0 || lower.rfind(name, 0) == 0) {
      extends = &candidate;
      ++extending;
    }
    const size_t distance = EditDistance(lower, name);
    if (distance < best_distance) {
      best_distance = distance;
      best = &candidate;
    }
  }
  if (best == nullptr && extending == 1) best = extends;
  if (best == nullptr) return "";
  return " (did you mean '" + std::string(prefix) + *best + "'?)";
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
