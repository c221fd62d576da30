// Reading the sound track of a video (or of any media file FFmpeg reads) in the engine's internal format,
// 16 kHz mono float, the same way readAudioFile reads a recording.
//
//   th::audio::AudioClip clip = th::audio::readMediaAudio(th::sharedDataPath("grid/s1/bbal7s.mpg"));
//   // clip.samples at clip.sampleRateHz == 16000; clip.sourceRateHz == 44100 (the file's own rate)
//
// The audio stream of the file (MPEG-1/2 program streams such as GRID's .mpg, MP4, AVI, MKV, and plain
// audio files: WAV, FLAC, MP3, ...) is decoded with FFmpeg's libraries, mixed to mono (channel mean) and
// resampled with the same libsoxr resampler as readAudioFile. Only local files are opened (no network or
// other FFmpeg protocols, even when a playlist inside the file names them). Bad input throws th::Error with
// one line "PATH: what is wrong" (missing, not a media file, no audio stream, undecodable, no samples,
// NaN/inf or absurdly large samples, unsupported rate); FFmpeg's own logging is switched off for the whole
// process on first use. Thread contract: no shared state besides that one-time switch; call from any thread.
#pragma once

#include <filesystem>

#include "audio/audio_file.h"

namespace th::audio {

// Decodes the audio stream of `path` (FFmpeg's pick when there are several: the one marked default, else
// normally the first), downmixes it (channel mean) and resamples it to options.outputRateHz (0 keeps the
// stream's rate). Time 0 of the clip is the first decoded sample, whatever the stream's start time.
AudioClip readMediaAudio(const std::filesystem::path& path, const AudioReadOptions& options = {});

// Any recording: sound files that libsndfile reads (by extension: .wav .flac .ogg .aiff .au .w64 .caf) through
// readAudioFile, everything else (videos, MP3, ...) through readMediaAudio.
AudioClip readRecording(const std::filesystem::path& path, const AudioReadOptions& options = {});

}  // namespace th::audio
