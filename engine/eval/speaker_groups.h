// Who speaks in each clip of a corpus whose speakers are not labelled (the Arabic news anchors: a thousand clips
// of dozens of people), so that an evaluation can hold speakers out.
//
//   std::vector<th::eval::ClipIdentity> ids = th::eval::clipIdentities(clips);   // clips of a TalkingCorpus
//   th::eval::SpeakerGroups groups = th::eval::groupSpeakers(ids, {.speakers = 60, .families = 2});
//   // groups.speaker[i]: clip i's speaker group; groups.family[i]: the wider group it belongs to
//
// A clip's identity is what stays the same while a person speaks: the face's shape (the tracked landmarks of the
// brows, eyes, nose and upper jaw line, each frame turned and scaled so the eyes lie level one unit apart, averaged
// over the frames), the voice (the median pitch, and the mean spectrum: MFCCs c1..c11 over the louder frames)
// and the look of the picture (the mean colour of a 3 x 3 grid over one frame: hair, skin, clothes, studio). The
// parts are put on one scale (principal components whitened for the face and the colours, z-scores for the voice)
// and weighed: pitch 3, colours 2, face 1, spectrum 0.3 (chosen by looking at the groups they make: pitch splits
// men from women surely, colour keeps a broadcast together, the face tells people of one look apart).
// Clips are grouped twice, by agglomerative clustering with Ward's linkage: into `families` by the pitch alone
// (a person's pitch does not change with the studio or the camera, so all of a person's clips fall in one family;
// with two, men's and women's voices), then each family into speaker groups (mostly one person each; as many as
// the family's share of `speakers`) by everything above. An evaluation that holds a speaker group out keeps its
// whole family out of training, so that the same person in another group is not trained on either.
// Thread contract: pure functions; clipIdentities reads files on a few threads.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "eval/talking_corpus.h"

namespace th::eval {

struct ClipIdentity {
  Eigen::VectorXd face;      // the mean normalised landmark shape (2 x 41 values)
  double logPitch = 0.0;     // log of the median F0 (Hz) of the voiced frames; NaN when none is voiced
  Eigen::VectorXd spectrum;  // mean MFCCs c1..c11 of the louder frames
  Eigen::VectorXd colours;   // mean BGR of a 3 x 3 grid over one frame (27 values, 0..255)
};

// Each clip's face from its kept track (TalkingClip::trackFile), its voice from its sound, its colours from its
// video. Errors name the file.
std::vector<ClipIdentity> clipIdentities(const std::vector<const TalkingClip*>& clips, unsigned threads = 0);

struct SpeakerGroupOptions {
  int speakers = 60;  // speaker groups in all
  int families = 2;   // by pitch
  double pitchWeight = 3.0;
  double colourWeight = 2.0;
  double faceWeight = 1.0;
  double spectrumWeight = 0.3;
  int faceComponents = 8;
  int colourComponents = 6;
};

struct SpeakerGroups {
  std::vector<int> speaker;  // per clip, 0 .. about speakers − 1; each group lies in one family
  std::vector<int> family;   // per clip, 0 .. families − 1
};

SpeakerGroups groupSpeakers(const std::vector<ClipIdentity>& identities, const SpeakerGroupOptions& options = {});

}  // namespace th::eval
