// What a face does besides speaking: it blinks, its eyes shift their gaze now and then, and its head comes to
// rest when nobody speaks. Laid over the live pipeline's frames at display time (the decoders know nothing of
// it), so it goes on when no sound comes at all.
//
//   th::animation::IdleMotion idle({});
//   idle.apply(secondsSinceStart, frame.levelDb, {.blinks = true, .gaze = true}, faps);   // every display frame
//   th::animation::addIdleMotion(animation, levelDb, {}, {});     // the same over a whole animation (files)
//
// Blinks: spontaneous blinks come about 17 a minute in adults at rest (Bentivoglio et al. 1997, Movement
// Disorders 12(6): 17 a minute at rest, 26 in conversation), never closer than a second apart; the intervals
// are drawn from a gamma distribution (shape 3, our choice: less bursty than a Poisson process). They follow
// speech as people's do (speakers blink at phrase boundaries and seldom mid-word: Cummins 2012, "Gaze and
// blinking in dyadic conversation"; Nakano & Kitazawa 2010): while the voice is on, the spontaneous clock runs
// at speechBlinkFactor of its pace, and where a phrase ends (boundaryPauseSeconds of quiet after at least
// boundarySpeechSeconds of speech) a blink follows with boundaryBlinkProbability. A blink closes the top lids in
// 80 ms, holds 30 ms and opens in 150 ms (the opening is the slower phase). Gaze: a fixation holds for 1–5 s, then a 50
// ms saccade moves the eyes to a point within a few degrees, half the time back to the centre. Head: a frame is speech
// if its level is speechMarginDb over the floor (a slow follower of the quietest level); after restAfterSeconds without
// speech the head's rotation eases to its rest pose (the mean pose, or headRestDegrees) with time constant restSeconds,
// and back when speech returns.
//
// Thread contract: one thread (the render thread); deterministic for a seed.
#pragma once

#include <Eigen/Core>
#include <array>
#include <random>

#include "face/face_model.h"
#include "face/fap_track.h"

namespace th::animation {

struct IdleMotionOptions {
  double blinksPerMinute = 17.0;
  double minBlinkGapSeconds = 1.0;
  double speechBlinkFactor = 0.5;         // the spontaneous blinks' pace while the voice is on
  double boundaryBlinkProbability = 0.8;  // a blink where a phrase ends
  double boundaryPauseSeconds = 0.15;     // quiet that ends a phrase
  double boundarySpeechSeconds = 0.4;     // speech that makes one
  double closeSeconds = 0.08;
  double closedSeconds = 0.03;
  double openSeconds = 0.15;
  double fixationMinSeconds = 1.0;
  double fixationMaxSeconds = 5.0;
  double gazeDegrees = 4.0;  // the largest shift off centre, yaw (pitch: half of it)
  double saccadeSeconds = 0.05;
  double speechMarginDb = 12.0;
  double floorRiseDbPerSecond = 1.0;  // how fast the tracked floor follows a louder room
  double restAfterSeconds = 0.6;
  double restSeconds = 0.5;
  // The pose the head rests in (pitch, yaw, roll, degrees): the one a head style adds (head_style.h).
  Eigen::Vector3d headRestDegrees = Eigen::Vector3d::Zero();
  unsigned seed = 1;
};

struct IdleSwitches {
  bool blinks = true;
  bool gaze = true;
  bool restHead = true;
};

class IdleMotion {
 public:
  explicit IdleMotion(const IdleMotionOptions& options = {});

  // Moves to `seconds` (non-decreasing) with the sound's level there (dB re full scale; very low for none):
  // sets the eyelid FAPs (19, 20) and the eyeball FAPs (23–26), and eases the head FAPs (48–50) toward rest.
  void apply(double seconds, double levelDb, const IdleSwitches& switches, face::FapFrame& faps);

  bool speaking() const { return speaking_; }
  double headGain() const { return headGain_; }           // 1 while speaking, easing to 0 at rest
  int blinks() const { return blinks_; }                  // blinks begun so far
  int boundaryBlinks() const { return boundaryBlinks_; }  // of them, at a phrase's end
  double blinkStart() const { return blinkStart_; }       // of the latest blink (< 0: none yet)
  double yawDegrees() const { return yaw_; }              // the gaze now
  double pitchDegrees() const { return pitch_; }

 private:
  double uniform(double low, double high);
  void scheduleBlink();
  void startBlink(bool atBoundary);
  void scheduleFixation(double after);
  double blinkClosure(bool voice, double elapsed);
  void followGaze();

  IdleMotionOptions options_;
  std::mt19937 random_;
  bool started_ = false;
  double now_ = 0.0;
  // Blinks
  double blinkDue_ = 0.0;        // seconds of the spontaneous clock to the next blink
  double boundaryBlink_ = -1.0;  // when a blink at a phrase's end is due (< 0: none)
  double blinkStart_ = -1.0;
  int blinks_ = 0;
  int boundaryBlinks_ = 0;
  double voiceStart_ = -1.0;  // the current stretch of voice began (< 0: quiet)
  double lastVoice_ = -1e9;
  double voicedRun_ = 0.0;  // how long the last stretch of speech lasted
  // Gaze
  double nextFixation_ = 0.0;
  double saccadeStart_ = -1.0;
  double fromYaw_ = 0.0, fromPitch_ = 0.0, toYaw_ = 0.0, toPitch_ = 0.0;
  double yaw_ = 0.0, pitch_ = 0.0;
  // Speech and the head
  double floorDb_ = 0.0;
  double lastSpeech_ = -1e9;
  bool speaking_ = false;
  double headGain_ = 0.0;
};

// The FAPs the idle behaviour sets: the eyelids (19, 20) and the eyeballs (23–26).
inline constexpr std::array<int, 6> kIdleFaps{19, 20, 23, 24, 25, 26};

// The idle behaviour over a whole animation, frame i at i / fps, for the outputs made from files (animate,
// export, render, sidebyside): the eyelid and eyeball FAPs (19, 20, 23–26) are added (or overlaid), and the head
// FAPs (48–50), where present, eased to rest in silence. levelDb: the sound's level per frame; empty when there
// is no sound to hear (the face counts as speaking: blinks and gaze, the head untouched).
void addIdleMotion(face::FapTrack& animation, const Eigen::RowVectorXd& levelDb, const IdleMotionOptions& options,
                   const IdleSwitches& switches);

}  // namespace th::animation
