// The viseme weight formats: Oculus/OpenXR's 15 visemes and VRM's five vowels, a row of weights per frame, as
// CSV or JSON (weight_tables.h). The weights are the viseme model's class probabilities (face/visemes.h).
#include <ostream>

#include "core/error.h"
#include "face/visemes.h"
#include "formats/animation_format.h"
#include "formats/weight_tables.h"

namespace th::formats {
namespace {

enum class Table { kOculus, kVrm };
enum class Layout { kCsv, kJson };

class VisemeWeightFormat final : public AnimationFormat {
 public:
  VisemeWeightFormat(Table table, Layout layout) : table_(table), layout_(layout) {}

  std::string_view name() const override {
    if (table_ == Table::kOculus) return layout_ == Layout::kCsv ? "oculus" : "oculus-json";
    return layout_ == Layout::kCsv ? "vrm" : "vrm-json";
  }
  std::string_view extension() const override { return layout_ == Layout::kCsv ? ".csv" : ".json"; }
  std::string_view description() const override {
    if (table_ == Table::kOculus)
      return layout_ == Layout::kCsv ? "Oculus/OpenXR's 15 viseme weights per frame (sil PP FF ... ou)"
                                     : "the Oculus viseme weights as JSON";
    return layout_ == Layout::kCsv ? "VRM's five vowel weights per frame (A I U E O)" : "the VRM vowel weights as JSON";
  }
  void check(const std::filesystem::path& path, const face::FapTrack& track) const override {
    checkVisemes(path, track);
  }
  void write(std::ostream& out, const face::FapTrack& track) const override {
    const face::VisemeTrack& visemes = track.visemes;
    const bool oculus = table_ == Table::kOculus;
    Eigen::MatrixXd weights(oculus ? face::kNumOculusVisemes : 5, visemes.numFrames());
    for (int t = 0; t < visemes.numFrames(); ++t)
      weights.col(t) =
          oculus ? face::oculusWeights(visemes.posteriors.col(t)) : face::vrmWeights(visemes.posteriors.col(t));
    const std::span<const std::string_view> names = oculus ? std::span<const std::string_view>(face::kOculusVisemeNames)
                                                           : std::span<const std::string_view>(face::kVrmVowelNames);
    if (layout_ == Layout::kCsv)
      writeWeightsCsv(out, names, weights, visemes.framesPerSecond);
    else
      writeWeightsJson(out, names, weights, visemes.framesPerSecond);
  }

 private:
  Table table_;
  Layout layout_;
};

}  // namespace

void checkVisemes(const std::filesystem::path& path, const face::FapTrack& track) {
  if (track.visemes.empty())
    throw fileError(path, "the animation has no visemes (animate with a viseme model: --viseme-model)");
  if (track.visemes.numFrames() != track.numFrames() || track.visemes.posteriors.cols() != track.numFrames() ||
      track.visemes.posteriors.rows() != face::kNumMouthClasses)
    throw fileError(path, "the visemes do not match the animation's frames");
}

const AnimationFormat& oculusFormat() {
  static const VisemeWeightFormat format(Table::kOculus, Layout::kCsv);
  return format;
}
const AnimationFormat& oculusJsonFormat() {
  static const VisemeWeightFormat format(Table::kOculus, Layout::kJson);
  return format;
}
const AnimationFormat& vrmFormat() {
  static const VisemeWeightFormat format(Table::kVrm, Layout::kCsv);
  return format;
}
const AnimationFormat& vrmJsonFormat() {
  static const VisemeWeightFormat format(Table::kVrm, Layout::kJson);
  return format;
}

}  // namespace th::formats
