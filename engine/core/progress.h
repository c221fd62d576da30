// A one-line progress bar for long jobs (exports, training) on a terminal:
//
//   th::ProgressBar bar(audioSeconds, "export", std::cerr);    // total in seconds of media
//   for (...) bar.update(framesDone / fps);
//   bar.finish();   // "export [##############################] 100% 12.3 s elapsed, 3.1x real time\n"
//
// On a terminal (the stream is std::cerr/std::clog and stderr is a tty, or std::cout and stdout is one) the line
// is redrawn in place with '\r', at most ten times a second (update() is cheap to call per frame); elsewhere
// (logs, pipes, CI, string streams) nothing is printed until finish() writes the final line once. The real-time
// factor is media seconds done per wall-clock second: `done / unitsPerSecond / elapsed` (unitsPerSecond 1:
// `total` and `done` are seconds; the frame rate: they are frames; 0: no factor shown).
// Destroyed without finish() (an exception), a drawn line is ended with a newline so later messages start on
// their own line. Thread contract: one thread per instance.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <ostream>
#include <string>

namespace th {

struct ProgressOptions {
  double unitsPerSecond = 1.0;    // units of total/done per second of media, for the real-time factor
  int barWidth = 30;              // characters between the brackets
  std::optional<bool> terminal;   // unset: detected from the stream (see above)
  std::function<double()> clock;  // seconds on any fixed origin; unset: std::chrono::steady_clock
};

class ProgressBar {
 public:
  ProgressBar(double total, std::string label, std::ostream& out, ProgressOptions options = {});
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // Progress so far, in the units of total (clamped to [0, total]); redraws when due, on a terminal.
  void update(double done);
  // Prints the final line (at the last update's progress) and a newline; later calls do nothing.
  void finish();

  bool drawsInPlace() const { return terminal_; }
  double elapsedSeconds() const;
  // The text of the line at `done` units, as it would be drawn now.
  std::string line(double done) const;

 private:
  void draw(bool final);

  double total_;
  std::string label_;
  std::ostream& out_;
  ProgressOptions options_;
  bool terminal_ = false;
  double start_ = 0.0;
  double done_ = 0.0;
  double lastDraw_ = 0.0;
  bool drawn_ = false;
  bool finished_ = false;
  std::size_t lastLength_ = 0;
};

}  // namespace th
