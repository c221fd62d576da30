#include "face/visemes.h"

#include <cctype>
#include <string>

namespace th::face {
namespace {

struct PhoneClass {
  std::string_view phone;
  MouthClass mouthClass;
};

constexpr PhoneClass kPhoneClasses[] = {
    {"", kSilence}, {"SIL", kSilence}, {"SP", kSilence}, {"SPN", kSilence}, {"NSN", kSilence}, {"B", kPp},  {"M", kPp},
    {"P", kPp},     {"F", kFf},        {"V", kFf},       {"TH", kTh},       {"DH", kTh},       {"T", kDd},  {"D", kDd},
    {"K", kKk},     {"G", kKk},        {"NG", kKk},      {"HH", kKk},       {"CH", kCh},       {"JH", kCh}, {"SH", kCh},
    {"ZH", kCh},    {"S", kSs},        {"Z", kSs},       {"N", kNn},        {"L", kL},         {"R", kRr},  {"ER", kRr},
    {"AA", kAa},    {"AW", kAa},       {"AY", kAa},      {"AE", kAh},       {"AH", kAh},       {"EH", kE},  {"EY", kE},
    {"IH", kIh},    {"IY", kIh},       {"Y", kIh},       {"AO", kOh},       {"OW", kOh},       {"OY", kOh}, {"UH", kOu},
    {"UW", kOu},    {"W", kOu},
};

// Oculus viseme of each class: the split classes (L, ah) go back to nn and aa.
constexpr std::array<int, kNumMouthClasses> kOculusOf{0, 1, 2, 3, 4, 5, 6, 7, 8, 8, 9, 10, 10, 11, 12, 13, 14};
constexpr std::string_view kRhubarbOf = "XAGBBBBBBHEDCCBEF";

// VRM A I U E O per class: vowels are their vowel; consonants lean to the vowel their lips resemble.
constexpr double kVrmOf[kNumMouthClasses][5] = {
    {0.0, 0.0, 0.0, 0.0, 0.0},  // sil
    {0.0, 0.0, 0.0, 0.0, 0.0},  // PP: lips closed
    {0.0, 0.2, 0.0, 0.0, 0.0},  // FF
    {0.0, 0.0, 0.0, 0.3, 0.0},  // TH
    {0.0, 0.0, 0.0, 0.3, 0.0},  // DD
    {0.2, 0.0, 0.0, 0.2, 0.0},  // kk
    {0.0, 0.0, 0.5, 0.0, 0.0},  // CH: protruded
    {0.0, 0.4, 0.0, 0.0, 0.0},  // SS: spread
    {0.0, 0.0, 0.0, 0.3, 0.0},  // nn
    {0.3, 0.0, 0.0, 0.2, 0.0},  // L
    {0.0, 0.0, 0.3, 0.0, 0.5},  // RR: rounded
    {1.0, 0.0, 0.0, 0.0, 0.0},  // aa
    {0.6, 0.0, 0.0, 0.3, 0.0},  // ah
    {0.0, 0.0, 0.0, 1.0, 0.0},  // E
    {0.0, 1.0, 0.0, 0.0, 0.0},  // ih
    {0.0, 0.0, 0.0, 0.0, 1.0},  // oh
    {0.0, 0.0, 1.0, 0.0, 0.0},  // ou
};

}  // namespace

int mouthClassOfPhone(std::string_view phone) {
  std::string bare;
  for (char c : phone)
    if (!std::isdigit(static_cast<unsigned char>(c)))
      bare += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  for (const PhoneClass& entry : kPhoneClasses)
    if (entry.phone == bare) return entry.mouthClass;
  return -1;
}

int oculusVisemeOf(int mouthClass) {
  return kOculusOf.at(static_cast<std::size_t>(mouthClass));
}

Eigen::VectorXd oculusWeights(const Eigen::Ref<const Eigen::VectorXd>& classProbabilities) {
  Eigen::VectorXd weights = Eigen::VectorXd::Zero(kNumOculusVisemes);
  for (int c = 0; c < kNumMouthClasses; ++c) weights[kOculusOf[static_cast<std::size_t>(c)]] += classProbabilities[c];
  return weights;
}

Eigen::VectorXd vrmWeights(const Eigen::Ref<const Eigen::VectorXd>& classProbabilities) {
  Eigen::VectorXd weights = Eigen::VectorXd::Zero(5);
  for (int c = 0; c < kNumMouthClasses; ++c)
    for (int v = 0; v < 5; ++v) weights[v] += classProbabilities[c] * kVrmOf[c][v];
  return weights.cwiseMin(1.0).cwiseMax(0.0);
}

char rhubarbShapeOf(int mouthClass) {
  return kRhubarbOf.at(static_cast<std::size_t>(mouthClass));
}

std::vector<Run> runsOf(const std::vector<int>& values) {
  std::vector<Run> runs;
  for (int t = 0; t < static_cast<int>(values.size()); ++t) {
    if (runs.empty() || runs.back().value != values[static_cast<std::size_t>(t)])
      runs.push_back({t, 0, values[static_cast<std::size_t>(t)]});
    ++runs.back().length;
  }
  return runs;
}

}  // namespace th::face
