// Videos the tracking tests make for themselves: one without a face, one without sound.
#pragma once

#include <filesystem>

namespace th::test {

// An MP4 (H.264 + AAC) of a grey gradient that drifts, 2 s at 25 fps, 320x240, with a 220 Hz tone: a video
// and a sound, but no face.
void writeFacelessVideo(const std::filesystem::path& path);

// The frames of `source` (any video VideoReader reads) as Motion-JPEG in an AVI, with no sound track.
void writeSoundlessCopy(const std::filesystem::path& source, const std::filesystem::path& path);

}  // namespace th::test
