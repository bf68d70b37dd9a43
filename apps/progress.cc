#include "apps/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "io/text_util.h"

namespace clothfit {
namespace progress {
namespace {

bool quiet = false;
bool line_shown = false;  // a progress line is on the terminal
std::vector<std::string>& HeldWarnings() {
  static std::vector<std::string> warnings;
  return warnings;
}

std::string Duration(double seconds) {
  if (seconds < 120.0) {
    return std::to_string(static_cast<long>(std::lround(seconds))) + " s";
  }
  return std::to_string(static_cast<long>(std::lround(seconds / 60.0))) +
         " min";
}

std::string Count(double x) {
  return text_util::FormatNumber(std::round(x * 10.0) / 10.0);
}

void Draw(const std::string& text) {
  std::fprintf(stderr, "\r\033[K%s", text.c_str());
  std::fflush(stderr);
  line_shown = true;
}

}  // namespace

void SetQuiet(bool q) { quiet = q; }

bool Enabled() { return !quiet && isatty(STDERR_FILENO) == 1; }

std::string Line(const std::string& what, double done, double total,
                 const std::string& unit, double elapsed_s) {
  constexpr int kWidth = 20;
  const double share = total > 0.0 ? std::clamp(done / total, 0.0, 1.0) : 0.0;
  const int filled = static_cast<int>(share * kWidth);
  std::string line = what + ": [" + std::string(filled, '#') +
                     std::string(kWidth - filled, '.') + "] " + Count(done) +
                     "/" + Count(total) + (unit.empty() ? "" : " " + unit) +
                     ", " + Duration(elapsed_s);
  if (share > 0.0 && share < 1.0 && elapsed_s >= 1.0) {
    line += ", about " + Duration(elapsed_s * (1.0 - share) / share) + " left";
  }
  return line;
}

Task::Task(std::string what, std::string unit)
    : what_(std::move(what)),
      unit_(std::move(unit)),
      start_(std::chrono::steady_clock::now()) {}

bool Task::Due() {
  if (!Enabled()) return false;
  const auto now = std::chrono::steady_clock::now();
  // Work shorter than half a second draws nothing (no flicker).
  if (now - start_ < std::chrono::milliseconds(500)) return false;
  if (drawn_ && now - last_draw_ < std::chrono::milliseconds(100)) {
    return false;
  }
  if (!drawn_) FlushWarnings();  // the input's warnings before the work
  last_draw_ = now;
  drawn_ = true;
  return true;
}

void Task::Update(double done, double total) {
  if (done >= total) {  // finished: the line goes
    if (drawn_) Clear();
    return;
  }
  if (!Due()) return;
  const double elapsed =
      std::chrono::duration<double>(last_draw_ - start_).count();
  Draw(Line(what_, done, total, unit_, elapsed));
}

void Task::Say(const std::string& text) {
  if (!Due()) return;
  const double elapsed =
      std::chrono::duration<double>(last_draw_ - start_).count();
  Draw(what_ + ": " + text + " (" + Duration(elapsed) + ")");
}

struct Activity::State {
  std::mutex mutex;
  std::condition_variable stop;
  bool stopping = false;
  std::thread thread;
};

Activity::Activity(std::string what) : state_(nullptr) {
  if (!Enabled()) return;
  FlushWarnings();
  state_ = new State;
  state_->thread = std::thread([state = state_, what = std::move(what)] {
    const auto start = std::chrono::steady_clock::now();
    std::unique_lock<std::mutex> lock(state->mutex);
    while (!state->stop.wait_for(lock, std::chrono::milliseconds(250),
                                 [state] { return state->stopping; })) {
      const double elapsed = std::chrono::duration<double>(
                                 std::chrono::steady_clock::now() - start)
                                 .count();
      if (elapsed >= 0.5) Draw(what + " (" + Duration(elapsed) + ")");
    }
  });
}

Activity::~Activity() {
  if (state_ == nullptr) return;
  {
    std::lock_guard<std::mutex> lock(state_->mutex);
    state_->stopping = true;
  }
  state_->stop.notify_one();
  state_->thread.join();
  delete state_;
  Clear();
}

void Clear() {
  if (!line_shown) return;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  line_shown = false;
}

void Warn(const std::string& text) { HeldWarnings().push_back(text); }

void FlushWarnings() {
  if (HeldWarnings().empty()) return;
  Clear();
  for (const std::string& text : HeldWarnings()) {
    std::fprintf(stderr, "warning: %s\n", text.c_str());
  }
  HeldWarnings().clear();
}

}  // namespace progress
}  // namespace clothfit
