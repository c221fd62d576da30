#include "face/fap.h"

#include <string>

#include "core/error.h"

namespace th::face {
namespace {

// Directions of positive motion in the face frame (+x the face's left, +y up, +z forward).
constexpr std::array<double, 3> kNoDirection{0, 0, 0};
constexpr std::array<double, 3> kUp{0, 1, 0};
constexpr std::array<double, 3> kDown{0, -1, 0};
constexpr std::array<double, 3> kLeft{1, 0, 0};    // the face's left
constexpr std::array<double, 3> kRight{-1, 0, 0};  // the face's right
constexpr std::array<double, 3> kForward{0, 0, 1};
// Rotation axes, signed so that a positive angle moves as the standard names it (right-hand rule):
constexpr std::array<double, 3> kPitchDown{1, 0, 0};  // +z turns towards −y
constexpr std::array<double, 3> kYawLeft{0, 1, 0};    // +z turns towards +x
constexpr std::array<double, 3> kRollRight{0, 0, 1};  // +y turns towards −x

using enum Fapu;

// Annex C of ISO/IEC 14496-2; names as the standard spells them (Candide-3 spells 61/62 "strecth").
constexpr std::array<FapDefinition, kNumFaps> kTable{{
    {1, "viseme", kNone, false, "", kNoDirection, "high-level"},
    {2, "expression", kNone, false, "", kNoDirection, "high-level"},
    {3, "open_jaw", kMns, false, "2.1", kDown, "jaw"},
    {4, "lower_t_midlip", kMns, true, "2.2", kDown, "inner lip"},
    {5, "raise_b_midlip", kMns, true, "2.3", kUp, "inner lip"},
    {6, "stretch_l_cornerlip", kMw, true, "2.4", kLeft, "inner lip"},
    {7, "stretch_r_cornerlip", kMw, true, "2.5", kRight, "inner lip"},
    {8, "lower_t_lip_lm", kMns, true, "2.6", kDown, "inner lip"},
    {9, "lower_t_lip_rm", kMns, true, "2.7", kDown, "inner lip"},
    {10, "raise_b_lip_lm", kMns, true, "2.8", kUp, "inner lip"},
    {11, "raise_b_lip_rm", kMns, true, "2.9", kUp, "inner lip"},
    {12, "raise_l_cornerlip", kMns, true, "2.4", kUp, "inner lip"},
    {13, "raise_r_cornerlip", kMns, true, "2.5", kUp, "inner lip"},
    {14, "thrust_jaw", kMns, false, "2.1", kForward, "jaw"},
    {15, "shift_jaw", kMw, true, "2.1", kRight, "jaw"},
    {16, "push_b_lip", kMns, true, "2.3", kForward, "inner lip"},
    {17, "push_t_lip", kMns, true, "2.2", kForward, "inner lip"},
    {18, "depress_chin", kMns, true, "2.10", kUp, "jaw"},
    {19, "close_t_l_eyelid", kIrisd, true, "3.1", kDown, "eyelid"},
    {20, "close_t_r_eyelid", kIrisd, true, "3.2", kDown, "eyelid"},
    {21, "close_b_l_eyelid", kIrisd, true, "3.3", kUp, "eyelid"},
    {22, "close_b_r_eyelid", kIrisd, true, "3.4", kUp, "eyelid"},
    {23, "yaw_l_eyeball", kAngle, true, "3.5", kYawLeft, "eyeball"},
    {24, "yaw_r_eyeball", kAngle, true, "3.6", kYawLeft, "eyeball"},
    {25, "pitch_l_eyeball", kAngle, true, "3.5", kPitchDown, "eyeball"},
    {26, "pitch_r_eyeball", kAngle, true, "3.6", kPitchDown, "eyeball"},
    {27, "thrust_l_eyeball", kEs, true, "3.5", kForward, "eyeball"},
    {28, "thrust_r_eyeball", kEs, true, "3.6", kForward, "eyeball"},
    {29, "dilate_l_pupil", kIrisd, true, "3.5", kNoDirection, "eyeball"},
    {30, "dilate_r_pupil", kIrisd, true, "3.6", kNoDirection, "eyeball"},
    {31, "raise_l_i_eyebrow", kEns, true, "4.1", kUp, "eyebrow"},
    {32, "raise_r_i_eyebrow", kEns, true, "4.2", kUp, "eyebrow"},
    {33, "raise_l_m_eyebrow", kEns, true, "4.3", kUp, "eyebrow"},
    {34, "raise_r_m_eyebrow", kEns, true, "4.4", kUp, "eyebrow"},
    {35, "raise_l_o_eyebrow", kEns, true, "4.5", kUp, "eyebrow"},
    {36, "raise_r_o_eyebrow", kEns, true, "4.6", kUp, "eyebrow"},
    {37, "squeeze_l_eyebrow", kEs, true, "4.1", kRight, "eyebrow"},
    {38, "squeeze_r_eyebrow", kEs, true, "4.2", kLeft, "eyebrow"},
    {39, "puff_l_cheek", kEs, true, "5.1", kLeft, "cheek"},
    {40, "puff_r_cheek", kEs, true, "5.2", kRight, "cheek"},
    {41, "lift_l_cheek", kEns, false, "5.3", kUp, "cheek"},
    {42, "lift_r_cheek", kEns, false, "5.4", kUp, "cheek"},
    {43, "shift_tongue_tip", kMw, true, "6.1", kRight, "tongue"},
    {44, "raise_tongue_tip", kMns, true, "6.1", kUp, "tongue"},
    {45, "thrust_tongue_tip", kMw, true, "6.1", kForward, "tongue"},
    {46, "raise_tongue", kMns, true, "6.2", kUp, "tongue"},
    {47, "tongue_roll", kAngle, false, "6.3", kNoDirection, "tongue"},
    {48, "head_pitch", kAngle, true, "7.1", kPitchDown, "head"},
    {49, "head_yaw", kAngle, true, "7.1", kYawLeft, "head"},
    {50, "head_roll", kAngle, true, "7.1", kRollRight, "head"},
    {51, "lower_t_midlip_o", kMns, true, "8.1", kDown, "outer lip"},
    {52, "raise_b_midlip_o", kMns, true, "8.2", kUp, "outer lip"},
    {53, "stretch_l_cornerlip_o", kMw, true, "8.3", kLeft, "outer lip"},
    {54, "stretch_r_cornerlip_o", kMw, true, "8.4", kRight, "outer lip"},
    {55, "lower_t_lip_lm_o", kMns, true, "8.5", kDown, "outer lip"},
    {56, "lower_t_lip_rm_o", kMns, true, "8.6", kDown, "outer lip"},
    {57, "raise_b_lip_lm_o", kMns, true, "8.7", kUp, "outer lip"},
    {58, "raise_b_lip_rm_o", kMns, true, "8.8", kUp, "outer lip"},
    {59, "raise_l_cornerlip_o", kMns, true, "8.3", kUp, "outer lip"},
    {60, "raise_r_cornerlip_o", kMns, true, "8.4", kUp, "outer lip"},
    {61, "stretch_l_nose", kEns, true, "9.1", kLeft, "nose"},
    {62, "stretch_r_nose", kEns, true, "9.2", kRight, "nose"},
    {63, "raise_nose", kEns, true, "9.3", kUp, "nose"},
    {64, "bend_nose", kEns, true, "9.3", kRight, "nose"},
    {65, "raise_l_ear", kEns, true, "10.1", kUp, "ear"},
    {66, "raise_r_ear", kEns, true, "10.2", kUp, "ear"},
    {67, "pull_l_ear", kEns, true, "10.3", kLeft, "ear"},
    {68, "pull_r_ear", kEns, true, "10.4", kRight, "ear"},
}};

// The table is written in FAP order; make a slip there a compile error rather than a wrong lookup.
constexpr bool numberedInOrder() {
  for (int i = 0; i < kNumFaps; ++i)
    if (kTable[static_cast<std::size_t>(i)].number != i + 1) return false;
  return true;
}
static_assert(numberedInOrder());

}  // namespace

std::string_view fapuName(Fapu unit) {
  switch (unit) {
    case kMns:
      return "MNS";
    case kMw:
      return "MW";
    case kEns:
      return "ENS";
    case kEs:
      return "ES";
    case kIrisd:
      return "IRISD";
    case kAngle:
      return "AU";
    case kNone:
      break;
  }
  return "";
}

const FapDefinition& fapDefinition(int number) {
  if (number < 1 || number > kNumFaps)
    throw Error("FAP number " + std::to_string(number) + " is outside 1.." + std::to_string(kNumFaps));
  return kTable[static_cast<std::size_t>(number - 1)];
}

int fapNumber(std::string_view name) {
  for (const FapDefinition& fap : kTable)
    if (fap.name == name) return fap.number;
  return 0;
}

double FapUnits::of(Fapu unit) const {
  switch (unit) {
    case kMns:
      return mns;
    case kMw:
      return mw;
    case kEns:
      return ens;
    case kEs:
      return es;
    case kIrisd:
      return irisd;
    case kAngle:
      return kAngleUnit;
    case kNone:
      break;
  }
  return 0.0;
}

}  // namespace th::face
