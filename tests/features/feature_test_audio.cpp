#include "feature_test_audio.h"

#include <map>

#include "audio/audio_file.h"
#include "core/data_path.h"

namespace th::test {

const std::vector<float>& beat2Speech(double seconds) {
  static std::map<double, std::vector<float>> cache;
  auto found = cache.find(seconds);
  if (found != cache.end()) return found->second;
  static const audio::AudioClip clip = audio::readAudioFile(sharedDataPath("beat2/2_scott_0_1_1.wav"));
  const auto count = std::min(clip.samples.size(), static_cast<size_t>(seconds * clip.sampleRateHz));
  return cache
      .emplace(seconds, std::vector<float>(clip.samples.begin(), clip.samples.begin() + static_cast<long>(count)))
      .first->second;
}

}  // namespace th::test
