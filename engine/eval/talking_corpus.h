// Talking-face corpora as the mouth model trains and is judged on them: folders of clips, each tracked and
// paired with its sound (video_training.h, the sound's offset from the picture taken out), its speaker named,
// its phones or words read where the corpus has them (in the sound's time).
//
//   std::vector<th::tracking::TalkingFolder> folders = th::tracking::sharedTalkingFolders();
//   th::tracking::TalkingCorpus corpus = th::tracking::loadTalkingCorpus(folders, face, {.trackFolder = "tracks"});
//   for (const th::tracking::TalkingClip& clip : corpus.clips) use(clip.speaker, clip.clip.recording, clip.labels);
//
// Labels: GRID's `.align` beside a clip (words, in 1/25000 s), StyleTalk's `NAME_phonemes.json` (one ARPAbet
// phone index per 30 fps frame, named by `phindex.json` in the same folder), a Praat TextGrid's "phones" tier
// (BEAT2), the news anchors' `NAME.words.csv` (Arabic words with their times, turned into phones by
// phone_labels.h's arabicPhones). Phone classes for measuring lip shapes: phoneClassOf.
// Thread contract: loadTalkingCorpus tracks on threads of its own (as loadVideoCorpus); the rest are pure
// functions of files.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "tracking/video_training.h"

namespace th::eval {

struct TalkingFolder {
  std::filesystem::path folder;
  std::string speaker;  // every clip's; empty: each clip's name up to "_clip" ("Obama_clip2" -> "Obama"), else its name
};

// The shared data's talking corpora for the mouth (core/data_path.h): GRID's speaker s1 (grid/s1 and
// grid/s1-more, 320 clips) and StyleTalk's four speakers (talking/styletalk, 6 clips, silent videos with
// their WAVs).
std::vector<TalkingFolder> sharedTalkingFolders();

struct LabelInterval {
  double startSeconds = 0.0;
  double endSeconds = 0.0;
  std::string label;  // an ARPAbet phone without stress ("AA", "B", "SIL"), or a word ("bin", "sil")
};

struct TalkingClip {
  tracking::VideoClip clip;
  std::filesystem::path trackFile;  // where its track is kept (empty when tracks are not kept)
  std::string speaker;
  std::vector<LabelInterval> labels;  // phones, or words where labelsAreWords; empty where there are none
  bool labelsAreWords = false;
};

struct TalkingCorpus {
  std::vector<TalkingClip> clips;  // folder by folder, each by name
  std::vector<tracking::SkippedClip> skipped;
  std::vector<int> faps;  // the visual rows of every recording
  double trackingSeconds = 0.0;
};

// Every folder's clips through loadVideoCorpus (tracks kept in options.trackFolder / the folder's own name, so
// that folders keep theirs apart). progress(clipsDone, clipsTotal) over all folders.
TalkingCorpus loadTalkingCorpus(const std::vector<TalkingFolder>& folders, const face::FaceModel& face,
                                const tracking::VideoCorpusOptions& options = {},
                                const std::function<void(int, int)>& progress = {});

std::string speakerOfClip(const std::filesystem::path& video);  // the naming rule above, for an empty speaker

// Readers; errors name the file.
std::vector<LabelInterval> readGridAlignment(const std::filesystem::path& align);
std::vector<LabelInterval> readFramePhones(const std::filesystem::path& phonesJson,
                                           const std::filesystem::path& indexJson, double framesPerSecond = 30.0);
std::vector<LabelInterval> readTextGridPhones(const std::filesystem::path& textGrid);

// What a label says of the lips. Phones: ARPAbet. Words (GRID's vocabulary): the closure at the start of a word
// that opens with /b p m/ and the nucleus of a word whose vowel is open; see labelClassesAt.
enum class PhoneClass {
  kSilence,
  kBilabial,
  kLabiodental,
  kOpenVowel,
  kRoundedVowel,
  kSpreadVowel,
  kOtherVowel,
  kConsonant
};
PhoneClass phoneClassOf(const std::string& arpabet);
const char* phoneClassName(PhoneClass phoneClass);

// The class each frame (i / framesPerSecond) falls in, for `frames` frames. Phones: the phone's class over its
// whole interval. Words: kBilabial over the first 80 ms of a word that starts with a bilabial, kOpenVowel over
// the middle third of a word whose vowel is open, kSilence in "sil", else kConsonant (no claim).
std::vector<PhoneClass> labelClassesAt(const std::vector<LabelInterval>& labels, bool labelsAreWords,
                                       double framesPerSecond, Eigen::Index frames);

}  // namespace th::eval
