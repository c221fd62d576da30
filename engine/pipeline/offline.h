// The offline path, whole recordings without a real-time constraint: what `animate`, `export`, `render`, `eval`
// and `sidebyside` run. Read top to bottom, it is the flow:
//
//   recording ─► speech features, computed once (animation/speech_analysis.h)
//             ─► head stage: prosody ─► rotations ─► FAPs 48–50 ───┐
//             ─► mouth stage: MFCCs ─► visual components ─► jaw and lip FAPs ─┐
//             ─► articulation: MFCCs at 90 fps ─► network stage ─► class stage: mouth classes (visemes,
//                Rhubarb's cues) ─► lips closed on PP, FF (without it, the viseme stage: each frame's mouth class)
//             ─► idle behaviour: blinks, gaze, the head at rest in silence
//             ─► FapTrack ─► an animation file (formats/), or the face rendered and encoded (video_export.h)
//
//   const th::pipeline::AnimationModels models = th::pipeline::loadAnimationModels(headPath, mouthPath);
//   th::face::FapTrack track = th::pipeline::animate(clip.samples, models, {});
//   th::formats::writeAnimation("speech.fap", track);
//
// Each stage is the one the live decoder runs (animation/online_stage.h's shape), chosen by the options
// (animation/recording_stages.h): the streaming stage where an option bounds the look-ahead (a lag ≥ 0, an
// inversion window), otherwise the batch decoder that hears the whole recording first. So `animate --online`
// runs the stages live runs.
// Each model normalises the speech it hears itself (features/speech_normaliser.h): each starts its running
// cepstral mean at its own training speech's mean, and the network hears 90 subframes a second, so one
// normalisation cannot serve them all without retraining them.
// Frame i is at i / 30 s for both parts. Head rotations are relative to the model's mean pose (the face's rest
// pose looks ahead). A model left out leaves its FAPs out.
// Thread contract: pure functions; models are shared read-only.
#pragma once

#include <filesystem>
#include <span>

#include "animation/articulation.h"
#include "animation/head_model.h"
#include "animation/idle_motion.h"
#include "animation/mouth_model.h"
#include "animation/speech_analysis.h"
#include "audio/audio_file.h"
#include "face/fap_track.h"
#include "pipeline/animation_models.h"

namespace th::pipeline {

struct AnimateOptions {
  animation::HeadSynthesisOptions head = {};    // variant; maxLagFrames ≥ 0 for the online (fixed-lag) decoder
  animation::MouthSynthesisOptions mouth = {};  // method; windowFrames > 0 for the streaming inversion
  bool idle = true;                             // blinks, gaze shifts and the head at rest in silence
  animation::IdleMotionOptions idleOptions = {};
  animation::ArticulationOptions articulation = {};
  // The articulation's classes: -1 decoded from the whole recording, its cepstral mean its own; ≥ 0 as a stream
  // decodes them (live's LiveDecoder): the training speech's mean to start from, decided this many frames late.
  int articulationLagFrames = -1;
};

// samples16k: mono at 16 kHz. Throws th::Error if both models are null, the mouth model drives no FAPs (no
// FAP map and no visual FAPs), or the recording is shorter than one frame.
// The articulation hears the whole recording (unless articulationLagFrames ≥ 0): its running cepstral mean
// starts at the recording's own mean (a stream starts at the training speech's and adapts within seconds).
face::FapTrack animate(std::span<const float> samples16k, const animation::HeadModel* head,
                       const animation::MouthModel* mouth, const AnimateOptions& options = {},
                       const animation::VisemeModel* visemes = nullptr,
                       const animation::MouthNetwork* articulation = nullptr);
face::FapTrack animate(std::span<const float> samples16k, const AnimationModels& models,
                       const AnimateOptions& options = {});

// A recording file (any that audio/media_audio.h reads, a video's sound track included) animated: the track
// named after the file, errors naming it. `clip`, if given, receives the sound.
face::FapTrack animateRecording(const std::filesystem::path& recording, const AnimationModels& models,
                                const AnimateOptions& options = {}, audio::AudioClip* clip = nullptr);

}  // namespace th::pipeline
