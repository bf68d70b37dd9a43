// Small text helpers shared by the readers/writers, the fits and the
// commands. Internal to clothfit; not part of the stable interface.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace clothfit {
namespace text_util {

// Longest excerpt of a field quoted in an error message.
inline constexpr size_t kMaxQuotedLength = 40;

// True for the ASCII whitespace characters " \t\r\n\v\f".
bool IsSpace(char c);

// `text` without leading and trailing ASCII whitespace.
std::string_view Trim(std::string_view text);

// ASCII-only lower-casing; other bytes pass through unchanged.
std::string Lower(std::string_view text);

// `text` with every byte that is not printable ASCII (and the backslash)
// written as \xNN: safe to print in a one-line message.
std::string Printable(std::string_view text);

// `text` with every control byte (below 0x20, and 0x7f: a newline in a file
// name) written as \xNN, other bytes (UTF-8 names) kept: a message stays on
// one line.
std::string EscapeControl(std::string_view text);

// Quotes (part of) a field for an error message: printable ASCII is kept,
// other bytes are escaped, fields longer than kMaxQuotedLength are shortened.
std::string Quote(std::string_view text);

// For a '#' line's text after the '#' that starts with the word `magic`
// (case-insensitive; e.g. "clothfit-table 1"): the rest, trimmed (the
// format version); nullopt for any other line.
std::optional<std::string> FormatVersion(std::string_view comment,
                                         std::string_view magic);

// Whether `text` ends with `suffix`.
bool EndsWith(std::string_view text, std::string_view suffix);

// Whether `path` ends with the file extension `extension` (".exr"), in any
// case ("G16.EXR").
bool HasExtension(std::string_view path, std::string_view extension);

// Splits `line` at every `separator`; always at least one field. A field
// in double quotes (spreadsheet CSV: "theta_i [deg]") may hold the
// separator; its view is the text between the quotes (a doubled quote ""
// inside stays doubled).
std::vector<std::string_view> SplitFields(std::string_view line,
                                          char separator = ',');

// `value` in the shortest form that reads back as the same double (0.35,
// not 0.34999999999999998; 1e-05): the form of clothfit's files and
// messages.
std::string FormatNumber(double value);
// `value` printed with "%.*g" at `significant` digits, for labels ("%.3g")
// and for numbers known only to that precision.
std::string FormatNumber(double value, int significant);

// For an unknown name `given`: " (did you mean 'X'?)" naming the candidate
// closest to it, when one is close (an edit distance, transpositions
// counted once, of at most a third of its length, at least 1; or a prefix
// of exactly one candidate, or a candidate that starts with it); else "".
// `prefix` is put before the name in the message ("--" for options).
std::string DidYouMean(std::string_view given,
                       const std::vector<std::string>& candidates,
                       std::string_view prefix = "");

// `text` with newlines replaced by spaces, so it fits on one '#' line.
std::string OneLine(std::string_view text);

}  // namespace text_util
}  // namespace clothfit
