#include "formats/mouth_cues.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "face/visemes.h"

namespace th::formats {

int durationCentiseconds(const face::FapTrack& track) {
  return static_cast<int>(std::floor(track.numFrames() * 100.0 / track.framesPerSecond + 1e-9));
}

std::vector<MouthCue> mouthCues(const face::FapTrack& track) {
  std::vector<int> shapes;
  for (int mouthClass : track.visemes.classes) shapes.push_back(face::rhubarbShapeOf(mouthClass));
  const int end = durationCentiseconds(track);
  std::vector<MouthCue> cues;
  for (const face::Run& run : face::runsOf(shapes)) {
    // Frame i is centred at i / fps and stands for the half frame either side: its cue starts half a frame early.
    const int start =
        std::max(0, static_cast<int>(std::lround((run.first - 0.5) * 100.0 / track.visemes.framesPerSecond)));
    if (start >= end) break;
    if (!cues.empty()) cues.back().endCs = start;
    cues.push_back({start, end, static_cast<char>(run.value)});
  }
  return cues;
}

std::string centiseconds(int cs) {
  char text[32];
  std::snprintf(text, sizeof text, "%d.%02d", cs / 100, cs % 100);
  return text;
}

}  // namespace th::formats
