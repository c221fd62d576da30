#include "core/progress.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <utility>

namespace th {
namespace {

constexpr double kRedrawInterval = 0.1;  // seconds: at most ten redraws a second

double steadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

bool isTerminal(const std::ostream& out) {
  if (&out == &std::cerr || &out == &std::clog) return ::isatty(STDERR_FILENO) == 1;
  if (&out == &std::cout) return ::isatty(STDOUT_FILENO) == 1;
  return false;
}

}  // namespace

ProgressBar::ProgressBar(double total, std::string label, std::ostream& out, ProgressOptions options)
    : total_(std::isfinite(total) ? std::max(total, 0.0) : 0.0),
      label_(std::move(label)),
      out_(out),
      options_(std::move(options)) {
  if (!options_.clock) options_.clock = steadySeconds;
  options_.barWidth = std::clamp(options_.barWidth, 1, 200);
  terminal_ = options_.terminal.has_value() ? *options_.terminal : isTerminal(out_);
  start_ = options_.clock();
}

ProgressBar::~ProgressBar() {
  if (terminal_ && drawn_ && !finished_) {
    out_ << '\n';
    out_.flush();
  }
}

double ProgressBar::elapsedSeconds() const {
  return std::max(0.0, options_.clock() - start_);
}

std::string ProgressBar::line(double done) const {
  const double fraction = total_ > 0.0 ? std::clamp(done / total_, 0.0, 1.0) : 1.0;
  const int width = options_.barWidth;
  const int filled = std::clamp(static_cast<int>(std::floor(fraction * width)), 0, width);
  std::string text = label_;
  if (!text.empty()) text += ' ';
  text += '[';
  text.append(static_cast<std::size_t>(filled), '#');
  text.append(static_cast<std::size_t>(width - filled), '.');
  text += ']';
  const double elapsed = elapsedSeconds();
  char numbers[96];
  std::snprintf(numbers, sizeof(numbers), " %3d%% %.1f s elapsed", static_cast<int>(std::floor(fraction * 100.0)),
                elapsed);
  text += numbers;
  if (options_.unitsPerSecond > 0.0 && elapsed > 0.0) {
    const double factor = std::clamp(done, 0.0, total_) / options_.unitsPerSecond / elapsed;
    std::snprintf(numbers, sizeof(numbers), ", %.1fx real time", factor);
    text += numbers;
  }
  return text;
}

void ProgressBar::update(double done) {
  if (finished_) return;
  done_ = std::isfinite(done) ? std::clamp(done, 0.0, total_) : done_;
  if (!terminal_) return;
  const double now = options_.clock();
  if (drawn_ && now - lastDraw_ < kRedrawInterval) return;
  lastDraw_ = now;
  draw(false);
}

void ProgressBar::finish() {
  if (finished_) return;
  finished_ = true;
  draw(true);
}

void ProgressBar::draw(bool final) {
  std::string text = line(done_);
  const std::size_t length = text.size();
  if (terminal_) {
    // Spaces over what is left of a longer previous line.
    if (length < lastLength_) text.append(lastLength_ - length, ' ');
    out_ << '\r' << text;
  } else {
    out_ << text;
  }
  if (final) out_ << '\n';
  out_.flush();
  lastLength_ = length;
  drawn_ = true;
}

}  // namespace th
