// Phones where a corpus has only words, and the mouth class of every frame from phones.
//
//   std::vector<th::eval::LabelInterval> phones = th::eval::gridPhones(th::eval::readGridAlignment(align));
//   std::vector<int> classes = th::eval::mouthClassesAt(phones, 30.0, frames);   // face::MouthClass, or -1
//
// GRID's sentences use 51 words; their ARPAbet pronunciations (as the CMU Pronouncing Dictionary gives them;
// the letters as spelt aloud) are written out here. A word's phones share its aligned interval in proportion
// to typical phone durations (vowels longest, diphthongs longer still, approximants shortest; after the
// segment durations of read American English in Crystal & House 1988), which puts a word-initial /b p m/ at
// the word's start for about its usual 60-90 ms. No acoustic alignment is done: where a phone falls within its
// word is an estimate, good to a phone's length.
// Thread contract: pure functions.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "eval/talking_corpus.h"

namespace th::eval {

// The ARPAbet phones of a GRID word ("bin" -> B IH N); empty for a word not in GRID's vocabulary.
std::vector<std::string> gridPronunciation(std::string_view word);

// GRID's word intervals (readGridAlignment) as phone intervals; "sil" and "sp" stay silence ("SIL"). Throws
// th::Error naming the word if one is not in the vocabulary.
std::vector<LabelInterval> gridPhones(const std::vector<LabelInterval>& words);

// The news clips' word timings (`conf,end,start,word` per line, seconds; a word with empty times was not
// placed). Errors name the file.
std::vector<LabelInterval> readWordTimings(const std::filesystem::path& csv);
// Arabic words as phone intervals (above); words without times are left out, so their frames stay unlabelled.
std::vector<LabelInterval> arabicPhones(const std::vector<LabelInterval>& words);
// One word's phones, for tests: ARPAbet labels and "?" for an unwritten vowel.
std::vector<std::string> arabicPronunciation(std::string_view word);

// A phone table, `start_s,end_s,phone` after that header line (tools/align_phones.py, tools/festival_speech.py).
// Errors name the file and the line.
std::vector<LabelInterval> readPhoneTable(const std::filesystem::path& csv);

// The mouth class (face::mouthClassOfPhone) of the phone under each frame's time (i / framesPerSecond), -1
// where no phone covers it or its label is no phone.
std::vector<int> mouthClassesAt(const std::vector<LabelInterval>& phones, double framesPerSecond, int frames);

}  // namespace th::eval
