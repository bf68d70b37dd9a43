// What a command says while it works, on standard error: a progress line
// on a terminal ("fit: [#######.............] 512/1365 texel fits, 12 s,
// about 20 s left"), redrawn in place and erased before anything else is
// printed; and warnings about the input, held until the command has
// checked its options (so that bad usage gets exactly one error line).
// No progress is drawn when standard error is not a terminal, or with
// --quiet.
#pragma once

#include <chrono>
#include <string>

namespace clothfit {
namespace progress {

// --quiet: no progress line (warnings and errors are still printed).
void SetQuiet(bool quiet);
// Whether progress lines are drawn: standard error is a terminal and
// --quiet was not given.
bool Enabled();

// The text of a progress line: "WHAT: [####......] DONE/TOTAL UNIT, E s"
// and, once a share is done and a second has passed, ", about R s left"
// (R from the rate so far). Times under 2 minutes in seconds, else in
// minutes.
std::string Line(const std::string& what, double done, double total,
                 const std::string& unit, double elapsed_s);

// One piece of long work. Updates are cheap: nothing is drawn in the first
// half second, then the line is redrawn at most ten times a second; the
// last step (done = total) erases it. Not thread-safe: a caller with
// threads serialises its calls.
class Task {
 public:
  // `what` starts the line ("fit", "reading T.csv"); `unit` follows the
  // counts ("texel fits", "MB").
  Task(std::string what, std::string unit);
  // done of total.
  void Update(double done, double total);
  // A step without a count: "WHAT: TEXT (E s)".
  void Say(const std::string& text);

 private:
  bool Due();
  std::string what_, unit_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  bool drawn_ = false;
};

// Work whose length is not known in advance (one library call): while it
// lives, a thread redraws "WHAT (E s)" every quarter second once half a
// second has passed; the line goes when it is destroyed. Nothing else may
// print meanwhile.
class Activity {
 public:
  explicit Activity(std::string what);
  ~Activity();
  Activity(const Activity&) = delete;
  Activity& operator=(const Activity&) = delete;

 private:
  struct State;
  State* state_;
};

// Erases the progress line, if one is shown.
void Clear();

// A warning ("warning: TEXT" on its own line), printed at the next
// FlushWarnings.
void Warn(const std::string& text);
// Prints the held warnings (erasing a progress line first). Called when
// the work starts and when a command ends, not on bad usage.
void FlushWarnings();

}  // namespace progress
}  // namespace clothfit
