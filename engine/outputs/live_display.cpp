#include "outputs/live_display.h"

#include <algorithm>
#include <cmath>

namespace th::outputs {

LiveDisplay::LiveDisplay(const pipeline::IdleOptions& idle, bool blinks, bool gaze)
    : on_(idle.idle), switches_{.blinks = blinks, .gaze = gaze}, idle_(idle.motionOptions()) {}

void LiveDisplay::setIdle(const pipeline::IdleOptions& idle) {
  on_ = idle.idle;
  idle_ = animation::IdleMotion(idle.motionOptions());
}

const AvatarFrame& LiveDisplay::present(pipeline::AnimationFrame& frame, double clockSeconds, bool send) {
  // A clock that goes back (a stream's own time, starting again) continues from where it was.
  if (clockSeconds + clockOffset_ < lastClock_) clockOffset_ = lastClock_ - clockSeconds;
  lastClock_ = clockSeconds + clockOffset_;
  if (frame.index < lastSent_) lastSent_ = -1;  // a new stream, frame 0 again
  if (on_) idle_.apply(lastClock_, frame.levelDb, switches_, frame.faps);
  shown_ = avatarFrameOf(frame);
  if (!send || frame.index == lastSent_ || outputs_.empty()) return shown_;
  lastSent_ = frame.index;
  for (const auto& output : outputs_) output->send(shown_);
  return shown_;
}

std::vector<int> LiveDisplay::fapNumbers(const std::vector<int>& decoded) const {
  std::vector<int> numbers = decoded;
  if (on_)
    for (const int fap : animation::kIdleFaps)
      if (std::find(numbers.begin(), numbers.end(), fap) == numbers.end()) numbers.push_back(fap);
  std::sort(numbers.begin(), numbers.end());
  return numbers;
}

std::vector<OutputStatus> LiveDisplay::statuses() const {
  std::vector<OutputStatus> statuses;
  for (const auto& output : outputs_) statuses.push_back(output->status());
  return statuses;
}

}  // namespace th::outputs
