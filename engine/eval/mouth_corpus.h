// The BEAT2 mouth corpus: per frame at 30 fps, the jaw opening (degrees, the x component of the SMPL-X jaw
// axis-angle; positive opens) and BEAT2's 100 FLAME expression coefficients, beside the speech frames of the
// synchronous recording (animation/mouth_data.h's MouthRecording). The talking-video corpora are
// talking_corpus.h's.
//
//   th::animation::MouthRecording take = th::eval::loadBeat2Mouth();
//
// Thread contract: pure functions of files.
#pragma once

#include <filesystem>

#include "animation/mouth_data.h"

namespace th::eval {

// A recording and its head-pose and expression CSVs (jaw_aa_x_deg; e0..e99). Errors name the file.
animation::MouthRecording loadMouthRecording(const std::filesystem::path& wav, const std::filesystem::path& headPoseCsv,
                                             const std::filesystem::path& expressionCsv);
animation::MouthRecording loadBeat2Mouth();

}  // namespace th::eval
