// What the tracking tests share: videos they make for themselves (one without a face, one without sound), and
// a recording's level per video frame, to hold the tracked mouth against.
#pragma once

#include <filesystem>
#include <vector>

#include "audio/audio_file.h"

namespace th::test {

// An MP4 (H.264 + AAC) of a grey gradient that drifts, 2 s at 25 fps, 320x240, with a 220 Hz tone: a video
// and a sound, but no face.
void writeFacelessVideo(const std::filesystem::path& path);

// The frames of `source` (any video VideoReader reads) as Motion-JPEG in an AVI, with no sound track.
void writeSoundlessCopy(const std::filesystem::path& source, const std::filesystem::path& path);

// The sound's level (dB of the mean square) over each of the first `frames` video frames at `framesPerSecond`
// (fewer if the sound ends first).
std::vector<double> levelPerFrame(const audio::AudioClip& sound, double framesPerSecond, std::size_t frames);

// Pearson's correlation of two equally long series.
double correlation(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace th::test
