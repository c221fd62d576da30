#include "eval/mouth_corpus.h"

#include <string>
#include <vector>

#include "core/data_path.h"
#include "core/error.h"
#include "core/numeric_csv.h"

namespace th::eval {
namespace {

constexpr int kExpressionCoefficients = 100;

}  // namespace

animation::MouthRecording loadMouthRecording(const std::filesystem::path& wav, const std::filesystem::path& headPoseCsv,
                                             const std::filesystem::path& expressionCsv) {
  const NumericTable pose = readNumericCsv(headPoseCsv);
  const NumericTable expressions = readNumericCsv(expressionCsv);
  const int jaw = pose.column("jaw_aa_x_deg");
  std::vector<int> columns;
  for (int k = 0; k < kExpressionCoefficients; ++k) columns.push_back(expressions.column("e" + std::to_string(k)));
  if (pose.rows.size() != expressions.rows.size()) {
    throw fileError(expressionCsv, "has " + std::to_string(expressions.rows.size()) + " frames, the head pose " +
                                       std::to_string(pose.rows.size()));
  }
  const animation::SpeechFrames speech = animation::speechFramesOf(wav);
  const int frames = std::min(static_cast<int>(pose.rows.size()), speech.numFrames());
  if (frames < 2) throw fileError(expressionCsv, "has fewer than 2 frames");
  animation::MouthRecording take;
  take.visual.resize(1 + kExpressionCoefficients, frames);
  for (int t = 0; t < frames; ++t) {
    take.visual(0, t) = pose.rows[static_cast<size_t>(t)][static_cast<size_t>(jaw)];
    for (int k = 0; k < kExpressionCoefficients; ++k) {
      take.visual(1 + k, t) =
          expressions.rows[static_cast<size_t>(t)][static_cast<size_t>(columns[static_cast<size_t>(k)])];
    }
  }
  take.speech = speech.middleFrames(0, frames);
  return take;
}

animation::MouthRecording loadBeat2Mouth() {
  return loadMouthRecording(sharedDataPath("beat2/2_scott_0_1_1.wav"),
                            sharedDataPath("beat2/2_scott_0_1_1_headpose_30fps.csv"),
                            sharedDataPath("beat2/2_scott_0_1_1_flame_expr_30fps.csv"));
}

}  // namespace th::eval
