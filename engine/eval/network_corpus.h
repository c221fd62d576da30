// The mouth network's corpus (animation/mouth_network.h): every talking clip with its sound's subframes, its
// tracked FAPs and lip shape, and its phones' mouth classes where it has phones; and phone-aligned speech without
// video. Each recording keeps its speaker and its set, so that evaluations can hold speakers out.
//
//   th::eval::TalkingCorpus talking = th::eval::loadTalkingCorpus(folders, face, options);
//   std::vector<th::eval::CorpusRecording> corpus = th::eval::networkRecordingsOf(talking);
//   for (th::eval::CorpusRecording& r : th::eval::phoneAlignedSpeech()) corpus.push_back(std::move(r));
//
// Classes: StyleTalk's per-frame phones and BEAT2's TextGrids as they are; GRID's words through its lexicon
// (phone_labels.h: phones placed within each word by typical durations), or its phones aligned to the sound
// (useAlignedPhones). Clips without phones (the Arabic
// anchors, GRID's other speakers without alignments) train and are judged on their lips alone.
// Thread contract: pure functions of files; networkRecordingsOf reads each clip's sound on a few threads.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "animation/mouth_network.h"
#include "eval/talking_corpus.h"

namespace th::eval {

struct CorpusRecording {
  animation::NetworkRecording recording;
  std::string set;  // the folder it came from: "grid/s1", "talking/styletalk", "talking/arabic-news", "beat2", ...
  const TalkingClip* clip = nullptr;  // the talking clip it was made from (nullptr: speech without video)
  // The same speech heard through other vocal tracts (speechSubframesOf's frequencyWarp), one per warp asked
  // for: more voices to train on, with the same truths.
  std::vector<animation::SpeechFrames> warped;
};

// Every clip of a loaded talking corpus; the corpus must outlive the result (clip points into it).
std::vector<CorpusRecording> networkRecordingsOf(const TalkingCorpus& corpus, const std::vector<double>& warps = {},
                                                 unsigned threads = 0);

// BEAT2's three phone-aligned takes (speaker "scott", set "beat2"): speech and classes, no video.
std::vector<CorpusRecording> phoneAlignedSpeech(const std::vector<double>& warps = {});

// A folder of phone-aligned speech: index.csv naming each file and its speaker (`file,speaker,text`), FILE.wav
// and FILE.phones.csv (`start_s,end_s,phone`, ARPAbet, SIL for pauses), as tools/align_phones.py writes it for a
// read corpus (speechocean762, or any WAVs with their words) and tools/festival_speech.py for Festival's voices.
// Each recording's set is `set`. Errors name the file.
std::vector<CorpusRecording> alignedSpeech(const std::filesystem::path& folder, const std::string& set,
                                           const std::vector<double>& warps = {});
// Festival's voices (tools/festival_speech.py): alignedSpeech with set "festival".
std::vector<CorpusRecording> synthesisedSpeech(const std::filesystem::path& folder,
                                               const std::vector<double>& warps = {});

// The talking clips that have only words (GRID's) take the phones a folder of tools/align_phones.py's holds for
// them (NAME.phones.csv beside the clip's name), where it has them: the phones where the sound puts them rather
// than placed by typical durations. Returns how many clips took them.
int useAlignedPhones(TalkingCorpus& corpus, const std::filesystem::path& folder);

// GRID s1's held-out clips: every fifth of each of its folders, in corpus order (as `eval mouth` holds out).
std::vector<bool> gridHeldOut(const std::vector<CorpusRecording>& corpus);

// Each recording's running cepstral mean set to start at its speaker's mean over the corpus (c1..c13): what a
// stream that has heard the speaker a while, or a whole recording, starts from.
void startAtSpeakerMeans(std::vector<CorpusRecording>& corpus);

// The mean of the recordings' tracked FAPs (rows: the corpus's FAPs): a typical open mouth. `include`, if given,
// picks the recordings counted.
Eigen::VectorXd meanFaps(const std::vector<CorpusRecording>& corpus,
                         const std::function<bool(const CorpusRecording&)>& include = {});

}  // namespace th::eval
