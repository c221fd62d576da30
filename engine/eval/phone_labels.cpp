#include "eval/phone_labels.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <sstream>

#include "core/error.h"
#include "core/text_files.h"
#include "face/visemes.h"

namespace th::eval {
namespace {

const std::map<std::string, std::string, std::less<>>& gridLexicon() {
  // clang-format off
  static const std::map<std::string, std::string, std::less<>> lexicon{
      // commands, colours, prepositions
      {"bin", "B IH N"}, {"lay", "L EY"}, {"place", "P L EY S"}, {"set", "S EH T"},
      {"blue", "B L UW"}, {"green", "G R IY N"}, {"red", "R EH D"}, {"white", "W AY T"},
      {"at", "AE T"}, {"by", "B AY"}, {"in", "IH N"}, {"with", "W IH DH"},
      // letters, as spelt aloud (GRID has no w)
      {"a", "EY"}, {"b", "B IY"}, {"c", "S IY"}, {"d", "D IY"}, {"e", "IY"}, {"f", "EH F"}, {"g", "JH IY"},
      {"h", "EY CH"}, {"i", "AY"}, {"j", "JH EY"}, {"k", "K EY"}, {"l", "EH L"}, {"m", "EH M"}, {"n", "EH N"},
      {"o", "OW"}, {"p", "P IY"}, {"q", "K Y UW"}, {"r", "AA R"}, {"s", "EH S"}, {"t", "T IY"}, {"u", "Y UW"},
      {"v", "V IY"}, {"x", "EH K S"}, {"y", "W AY"}, {"z", "Z IY"},
      // digits, adverbs
      {"zero", "Z IH R OW"}, {"one", "W AH N"}, {"two", "T UW"}, {"three", "TH R IY"}, {"four", "F AO R"},
      {"five", "F AY V"}, {"six", "S IH K S"}, {"seven", "S EH V AH N"}, {"eight", "EY T"}, {"nine", "N AY N"},
      {"again", "AH G EH N"}, {"now", "N AW"}, {"please", "P L IY Z"}, {"soon", "S UW N"}};
  // clang-format on
  return lexicon;
}

// A phone's typical share of a word: relative durations (Crystal & House 1988's read speech, rounded).
double relativeDuration(const std::string& phone) {
  if (phone == "?") return 0.8;  // an unwritten short vowel
  // clang-format off
  static const std::map<std::string, double, std::less<>> durations{
      {"AY", 1.9}, {"AW", 1.9}, {"OY", 1.9}, {"EY", 1.6}, {"OW", 1.6}, {"IY", 1.3}, {"UW", 1.3}, {"AA", 1.4},
      {"AE", 1.4}, {"AO", 1.4}, {"EH", 1.1}, {"IH", 0.9}, {"UH", 0.9}, {"AH", 0.8}, {"ER", 1.3},
      {"S", 1.2},  {"Z", 1.0},  {"F", 1.1},  {"V", 0.8},  {"TH", 1.0}, {"DH", 0.6}, {"SH", 1.2}, {"CH", 1.2},
      {"JH", 1.0}, {"P", 1.0},  {"B", 0.9},  {"T", 0.9},  {"D", 0.8},  {"K", 1.0},  {"G", 0.8},  {"M", 0.9},
      {"N", 0.8},  {"NG", 0.9}, {"L", 0.7},  {"R", 0.7},  {"W", 0.7},  {"Y", 0.6},  {"HH", 0.7}};
  // clang-format on
  const auto found = durations.find(phone);
  return found == durations.end() ? 1.0 : found->second;
}

// A word's phones over its interval, each a share as long as its typical duration.
void placePhones(const LabelInterval& word, const std::vector<std::string>& pronunciation,
                 std::vector<LabelInterval>& phones) {
  double total = 0.0;
  for (const std::string& phone : pronunciation) total += relativeDuration(phone);
  double start = word.startSeconds;
  for (const std::string& phone : pronunciation) {
    const double end = start + (word.endSeconds - word.startSeconds) * relativeDuration(phone) / total;
    phones.push_back({start, end, phone});
    start = end;
  }
  phones.back().endSeconds = word.endSeconds;
}

std::string lower(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

// Code points of a UTF-8 text (an invalid byte stands for itself; the words here are well formed).
std::vector<char32_t> codePoints(std::string_view text) {
  std::vector<char32_t> out;
  for (std::size_t i = 0; i < text.size();) {
    const auto byte = static_cast<unsigned char>(text[i]);
    int length = byte < 0x80 ? 1 : (byte >> 5) == 0x6 ? 2 : (byte >> 4) == 0xE ? 3 : (byte >> 3) == 0x1E ? 4 : 1;
    if (i + static_cast<std::size_t>(length) > text.size()) length = 1;
    char32_t point = length == 1 ? byte : byte & (0xFF >> (length + 1));
    for (int k = 1; k < length; ++k) point = (point << 6) | (static_cast<unsigned char>(text[i + k]) & 0x3F);
    out.push_back(point);
    i += static_cast<std::size_t>(length);
  }
  return out;
}

// Arabic letters and marks (Unicode block 0600-06FF).
constexpr char32_t kAlef = 0x0627, kAlefWasla = 0x0671, kAlefHamzaAbove = 0x0623, kAlefHamzaBelow = 0x0625,
                   kAlefMadda = 0x0622, kAlefMaksura = 0x0649, kTehMarbuta = 0x0629, kWaw = 0x0648, kYeh = 0x064A,
                   kLam = 0x0644, kTatweel = 0x0640;
constexpr char32_t kFathatan = 0x064B, kDammatan = 0x064C, kKasratan = 0x064D, kFatha = 0x064E, kDamma = 0x064F,
                   kKasra = 0x0650, kShadda = 0x0651, kSukun = 0x0652;

bool isMark(char32_t c) {
  return c >= kFathatan && c <= kSukun;
}

// The consonant a letter stands for (ARPAbet), or "" for a letter that is not a plain consonant.
std::string consonantOf(char32_t c) {
  // clang-format off
  static const std::map<char32_t, const char*> consonants{
      {U'ب', "B"}, {U'ت', "T"}, {U'ط', "T"}, {U'ث', "TH"}, {U'ج', "JH"}, {U'د', "D"}, {U'ض', "D"},
      {U'ذ', "DH"}, {U'ظ', "DH"}, {U'ر', "R"}, {U'ز', "Z"}, {U'س', "S"}, {U'ص', "S"}, {U'ش', "SH"},
      {U'ف', "F"}, {U'ق', "K"}, {U'ك', "K"}, {U'ل', "L"}, {U'م', "M"}, {U'ن', "N"},
      // the glottal stop (hamza on any seat but alef), h and the pharyngeals and uvulars
      {U'ء', "HH"}, {U'ؤ', "HH"}, {U'ئ', "HH"}, {U'ه', "HH"}, {U'ح', "HH"}, {U'خ', "HH"}, {U'ع', "HH"},
      {U'غ', "HH"}};
  // clang-format on
  const auto found = consonants.find(c);
  return found == consonants.end() ? "" : found->second;
}

// The sun letters: the article's lam is not said before them (the letter is doubled instead).
bool isSunLetter(char32_t c) {
  static constexpr std::u32string_view kSunLetters = U"تثدذرزسشصضطظلن";
  return kSunLetters.find(c) != std::u32string_view::npos;
}

// The marks after a letter, from `at` on (left past them): the vowel they say, and whether they settle the
// letter's vowel (a vowel mark or a sukun); a shadda sets `shadda`.
std::pair<std::vector<std::string>, bool> vowelOfMarks(const std::vector<char32_t>& letters, std::size_t& at,
                                                       bool& shadda) {
  std::vector<std::string> vowel;
  bool sukun = false, any = false;
  while (at < letters.size() && isMark(letters[at])) {
    any = true;
    switch (letters[at]) {
      case kFatha:
        vowel = {"AH"};
        break;
      case kKasra:
        vowel = {"IH"};
        break;
      case kDamma:
        vowel = {"UH"};
        break;
      case kFathatan:
        vowel = {"AH", "N"};
        break;
      case kKasratan:
        vowel = {"IH", "N"};
        break;
      case kDammatan:
        vowel = {"UH", "N"};
        break;
      case kShadda:
        shadda = true;
        break;
      case kSukun:
        sukun = true;
        break;
      default:
        break;
    }
    ++at;
  }
  return std::make_pair(vowel, any && (sukun || !vowel.empty()));
}

void appendToken(const std::vector<char32_t>& letters, std::vector<std::string>& phones) {
  std::size_t i = 0;
  bool geminateNext = false;
  // The article: its alef a vowel that may or may not be said, its lam silent before a sun letter.
  if (letters.size() > 2 && (letters[0] == kAlef || letters[0] == kAlefWasla) && letters[1] == kLam) {
    phones.push_back("?");
    i = 2;
    while (i < letters.size() && isMark(letters[i])) ++i;
    if (i < letters.size() && isSunLetter(letters[i])) {
      geminateNext = true;
    } else {
      phones.push_back("L");
    }
  }
  // Whether the last thing said was a consonant with no vowel of its own yet.
  bool pendingVowel = false;
  for (; i < letters.size();) {
    const char32_t c = letters[i++];
    if (c == kTatweel || isMark(c)) continue;
    const bool atStart = phones.empty() || i == 1;
    const bool last = i >= letters.size() || (i < letters.size() && std::all_of(letters.begin() + static_cast<long>(i),
                                                                                letters.end(), isMark));
    // Letters of prolongation: a long vowel after a consonant still waiting for its vowel.
    if (!atStart && (c == kAlef || c == kAlefMaksura) &&
        (pendingVowel || phones.back() == "AH" || phones.back() == "?")) {
      if (!pendingVowel) phones.pop_back();
      phones.push_back("AA");
      pendingVowel = false;
      continue;
    }
    if (c == kAlef || c == kAlefWasla) {  // a word's first alef: a vowel that may be elided
      phones.push_back("?");
      continue;
    }
    const bool nextIsMark = i < letters.size() && isMark(letters[i]);
    if (!atStart && !nextIsMark && (c == kWaw || c == kYeh) &&
        (pendingVowel || phones.back() == (c == kWaw ? "UH" : "IH"))) {
      if (!pendingVowel) phones.pop_back();
      phones.push_back(c == kWaw ? "UW" : "IY");
      pendingVowel = false;
      continue;
    }
    if (pendingVowel) phones.push_back("?");
    pendingVowel = false;
    std::string consonant;
    std::vector<std::string> implied;  // the vowel a hamza seat or a final letter implies
    if (c == kWaw)
      consonant = "W";
    else if (c == kYeh)
      consonant = "Y";
    else if (c == kAlefHamzaAbove)
      consonant = "HH";
    else if (c == kAlefHamzaBelow)
      consonant = "HH", implied = {"IH"};
    else if (c == kAlefMadda)
      consonant = "HH", implied = {"AA"};
    else if (c == kTehMarbuta)
      consonant = last ? "" : "T", implied = last ? std::vector<std::string>{"AH"} : implied;
    else
      consonant = consonantOf(c);
    if (consonant.empty() && implied.empty()) continue;  // a letter we do not know: nothing said for it
    bool shadda = geminateNext;
    geminateNext = false;
    const auto [vowel, marked] = vowelOfMarks(letters, i, shadda);
    if (!consonant.empty()) {
      phones.push_back(consonant);
      if (shadda) phones.push_back(consonant);
    }
    if (!vowel.empty()) {
      phones.insert(phones.end(), vowel.begin(), vowel.end());
    } else if (!implied.empty()) {
      phones.insert(phones.end(), implied.begin(), implied.end());
    } else if (!marked && !last && !consonant.empty()) {
      pendingVowel = true;
    }
  }
}

}  // namespace

std::vector<std::string> gridPronunciation(std::string_view word) {
  const auto found = gridLexicon().find(lower(word));
  if (found == gridLexicon().end()) return {};
  std::istringstream phones(found->second);
  std::vector<std::string> out;
  for (std::string phone; phones >> phone;) out.push_back(phone);
  return out;
}

std::vector<LabelInterval> gridPhones(const std::vector<LabelInterval>& words) {
  std::vector<LabelInterval> phones;
  for (const LabelInterval& word : words) {
    const std::string name = lower(word.label);
    if (name == "sil" || name == "sp") {
      phones.push_back({word.startSeconds, word.endSeconds, "SIL"});
      continue;
    }
    const std::vector<std::string> pronunciation = gridPronunciation(name);
    if (pronunciation.empty()) throw Error("GRID word \"" + word.label + "\" is not in GRID's vocabulary");
    placePhones(word, pronunciation, phones);
  }
  return phones;
}

std::vector<std::string> arabicPronunciation(std::string_view word) {
  std::vector<std::string> phones;
  std::vector<char32_t> token;
  for (const char32_t c : codePoints(word)) {
    if (c == U' ' || c == U'\t' || c == U'\r' || c == U'\n') {
      if (!token.empty()) appendToken(token, phones);
      token.clear();
    } else {
      token.push_back(c);
    }
  }
  if (!token.empty()) appendToken(token, phones);
  return phones;
}

std::vector<LabelInterval> readPhoneTable(const std::filesystem::path& csv) {
  std::istringstream text(readTextFile(csv, "phone list"));
  std::string line;
  if (!std::getline(text, line) || line.rfind("start_s,end_s,phone", 0) != 0)
    throw fileError(csv, "does not start with the header start_s,end_s,phone");
  std::vector<LabelInterval> phones;
  int number = 1;
  while (std::getline(text, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::istringstream fields(line);
    std::string start, end, phone;
    if (!std::getline(fields, start, ',') || !std::getline(fields, end, ',') || !std::getline(fields, phone, ','))
      throw fileError(csv, "line " + std::to_string(number) + " is not start_s,end_s,phone");
    try {
      const double s = std::stod(start), e = std::stod(end);
      if (!(s >= 0.0 && e >= s)) throw std::invalid_argument("order");
      phones.push_back({s, e, phone});
    } catch (const std::exception&) {
      throw fileError(csv, "line " + std::to_string(number) + ": times must be seconds, start <= end");
    }
  }
  return phones;
}

std::vector<LabelInterval> readWordTimings(const std::filesystem::path& csv) {
  std::istringstream text(readTextFile(csv, "word timings"));
  std::string line;
  if (!std::getline(text, line) || line.rfind("conf,end,start,word", 0) != 0)
    throw fileError(csv, "does not start with the header conf,end,start,word");
  std::vector<LabelInterval> words;
  int number = 1;
  while (std::getline(text, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    if (line.rfind("conf,end,start,word", 0) == 0) continue;  // the header again (22 of the clips repeat it)
    std::istringstream fields(line);
    std::string conf, end, start, word;
    if (!std::getline(fields, conf, ',') || !std::getline(fields, end, ',') || !std::getline(fields, start, ',') ||
        !std::getline(fields, word))
      throw fileError(csv, "line " + std::to_string(number) + " is not conf,end,start,word");
    if (start.empty() || end.empty()) continue;  // not placed by the aligner
    try {
      const double s = std::stod(start), e = std::stod(end);
      if (!(s >= 0.0 && e >= s)) throw std::invalid_argument("order");
      words.push_back({s, e, word});
    } catch (const std::exception&) {
      throw fileError(csv, "line " + std::to_string(number) + ": times must be seconds, start <= end");
    }
  }
  return words;
}

std::vector<LabelInterval> arabicPhones(const std::vector<LabelInterval>& words) {
  std::vector<LabelInterval> phones;
  for (const LabelInterval& word : words) {
    const std::vector<std::string> pronunciation = arabicPronunciation(word.label);
    if (pronunciation.empty()) continue;
    placePhones(word, pronunciation, phones);
  }
  return phones;
}

std::vector<int> mouthClassesAt(const std::vector<LabelInterval>& phones, double framesPerSecond, int frames) {
  std::vector<int> classes(static_cast<std::size_t>(std::max(frames, 0)), -1);
  std::size_t next = 0;
  for (int t = 0; t < frames; ++t) {
    const double seconds = t / framesPerSecond;
    while (next < phones.size() && phones[next].endSeconds <= seconds) ++next;
    if (next < phones.size() && phones[next].startSeconds <= seconds)
      classes[static_cast<std::size_t>(t)] = face::mouthClassOfPhone(phones[next].label);
  }
  return classes;
}

}  // namespace th::eval
