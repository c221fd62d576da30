#include "eval/talking_corpus.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "core/data_path.h"
#include "core/error.h"
#include "core/json_reading.h"
#include "core/text_files.h"
#include "eval/phone_labels.h"

namespace th::eval {

std::vector<TalkingFolder> sharedTalkingFolders() {
  return {{sharedDataPath("grid/s1"), "grid-s1"},
          {sharedDataPath("grid/s1-more"), "grid-s1"},
          {sharedDataPath("talking/styletalk"), ""}};
}

std::string speakerOfClip(const std::filesystem::path& video) {
  const std::string stem = video.stem().string();
  const std::size_t clip = stem.find("_clip");
  return clip == std::string::npos || clip == 0 ? stem : stem.substr(0, clip);
}

namespace {

// A folder's own name for its tracks: its last two path parts ("grid/s1" -> "grid_s1"), so that GRID's s1 and
// another corpus's s1 keep theirs apart.
std::string trackFolderName(const std::filesystem::path& folder) {
  const std::filesystem::path normal = folder.lexically_normal();
  std::filesystem::path last = normal.filename();
  if (last.empty()) last = normal.parent_path().filename();
  const std::filesystem::path parent =
      normal.filename().empty() ? normal.parent_path().parent_path() : normal.parent_path();
  const std::string name = parent.filename().empty() ? last.string() : parent.filename().string() + "_" + last.string();
  return name.empty() ? std::string("clips") : name;
}

std::string upper(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  return text;
}

// Labels beside a clip: GRID's NAME.align, or StyleTalk's NAME_phonemes.json with phindex.json.
void readLabelsBeside(TalkingClip& clip) {
  const std::filesystem::path video = clip.clip.video;
  std::filesystem::path align = video;
  align.replace_extension(".align");
  const std::filesystem::path phones = video.parent_path() / (video.stem().string() + "_phonemes.json");
  const std::filesystem::path index = video.parent_path() / "phindex.json";
  const std::filesystem::path words = video.parent_path() / (video.stem().string() + ".words.csv");
  std::error_code missing;
  if (std::filesystem::is_regular_file(align, missing)) {
    clip.labels = readGridAlignment(align);
    clip.labelsAreWords = true;
  } else if (std::filesystem::is_regular_file(phones, missing) && std::filesystem::is_regular_file(index, missing)) {
    clip.labels = readFramePhones(phones, index);
  } else if (std::filesystem::is_regular_file(words, missing)) {
    clip.labels = arabicPhones(readWordTimings(words));  // the news anchors' words, as phones
  }
}

}  // namespace

TalkingCorpus loadTalkingCorpus(const std::vector<TalkingFolder>& folders, const face::FaceModel& face,
                                const tracking::VideoCorpusOptions& options,
                                const std::function<void(int, int)>& progress) {
  std::vector<std::vector<std::filesystem::path>> videos;
  int total = 0;
  for (const TalkingFolder& folder : folders) {
    videos.push_back(tracking::listVideos(folder.folder));
    total += static_cast<int>(videos.back().size());
  }
  TalkingCorpus corpus;
  int doneBefore = 0;
  for (std::size_t f = 0; f < folders.size(); ++f) {
    tracking::VideoCorpusOptions folderOptions = options;
    if (!options.trackFolder.empty())
      folderOptions.trackFolder = options.trackFolder / trackFolderName(folders[f].folder);
    tracking::VideoCorpus loaded;
    try {
      loaded = tracking::loadVideoCorpus(videos[f], face, folderOptions, [&](int done, int) {
        if (progress) progress(doneBefore + done, total);
      });
    } catch (const Error& error) {
      throw fileError(folders[f].folder, error.what());
    }
    doneBefore += static_cast<int>(videos[f].size());
    corpus.faps = loaded.faps;
    corpus.trackingSeconds += loaded.trackingSeconds;
    for (tracking::SkippedClip& skipped : loaded.skipped) corpus.skipped.push_back(std::move(skipped));
    for (tracking::VideoClip& clip : loaded.clips) {
      TalkingClip talking;
      talking.speaker = folders[f].speaker.empty() ? speakerOfClip(clip.video) : folders[f].speaker;
      if (!folderOptions.trackFolder.empty())
        talking.trackFile = folderOptions.trackFolder / tracking::trackFileName(clip.video);
      talking.clip = std::move(clip);
      readLabelsBeside(talking);
      corpus.clips.push_back(std::move(talking));
    }
  }
  return corpus;
}

std::vector<LabelInterval> readGridAlignment(const std::filesystem::path& align) {
  std::istringstream text(readTextFile(align, "alignment"));
  std::vector<LabelInterval> words;
  std::string line;
  int number = 0;
  while (std::getline(text, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    std::istringstream fields(line);
    long long start = 0, end = 0;
    std::string word;
    if (!(fields >> start >> end >> word) || start < 0 || end < start)
      throw fileError(align, "line " + std::to_string(number) + " is not \"start end word\" (1/25000 s)");
    words.push_back({static_cast<double>(start) / 25000.0, static_cast<double>(end) / 25000.0, word});
  }
  if (words.empty()) throw fileError(align, "holds no words");
  return words;
}

std::vector<LabelInterval> readFramePhones(const std::filesystem::path& phonesJson,
                                           const std::filesystem::path& indexJson, double framesPerSecond) {
  const Json index = readJsonFile(indexJson, "phone index");
  if (!index.is_object() || index.empty()) throw fileError(indexJson, "is not a JSON object of phone names to numbers");
  std::vector<std::string> names;
  for (const auto& [name, value] : index.items()) {
    if (!value.is_number_integer() || value.get<int>() < 0 || value.get<int>() > 1000)
      throw fileError(indexJson, "phone " + name + " has no index 0..1000");
    const auto at = static_cast<std::size_t>(value.get<int>());
    if (names.size() <= at) names.resize(at + 1);
    names[at] = upper(name);
  }
  const Json frames = readJsonFile(phonesJson, "phones");
  if (!frames.is_array() || frames.empty()) throw fileError(phonesJson, "is not a JSON list of phone indices");
  std::vector<LabelInterval> phones;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (!frames[i].is_number_integer() || frames[i].get<int>() < 0 ||
        static_cast<std::size_t>(frames[i].get<int>()) >= names.size() || names[frames[i].get<std::size_t>()].empty())
      throw fileError(phonesJson, "frame " + std::to_string(i) + " has no phone of " + indexJson.filename().string());
    const std::string& name = names[frames[i].get<std::size_t>()];
    // Frame i is centred at i / fps: its phone covers half a frame either side.
    const double start = (static_cast<double>(i) - 0.5) / framesPerSecond;
    const double end = (static_cast<double>(i) + 0.5) / framesPerSecond;
    if (!phones.empty() && phones.back().label == name)
      phones.back().endSeconds = end;
    else
      phones.push_back({std::max(0.0, start), end, name});
  }
  return phones;
}

std::vector<LabelInterval> readTextGridPhones(const std::filesystem::path& textGrid) {
  // Praat's long text format: the tier named "phones", then its intervals' xmin, xmax and text.
  std::istringstream text(readTextFile(textGrid, "TextGrid"));
  std::string line;
  bool inPhones = false;
  std::vector<LabelInterval> phones;
  LabelInterval current;
  const auto valueOf = [](const std::string& l) {
    const std::size_t eq = l.find('=');
    std::string value = eq == std::string::npos ? std::string() : l.substr(eq + 1);
    value.erase(0, value.find_first_not_of(" \t"));
    while (!value.empty() && (value.back() == ' ' || value.back() == '\r')) value.pop_back();
    return value;
  };
  while (std::getline(text, line)) {
    const std::string trimmed = line.substr(std::min(line.size(), line.find_first_not_of(" \t")));
    if (trimmed.rfind("name =", 0) == 0) {
      inPhones = valueOf(trimmed) == "\"phones\"";
      continue;
    }
    if (!inPhones) continue;
    try {
      if (trimmed.rfind("xmin =", 0) == 0)
        current.startSeconds = std::stod(valueOf(trimmed));
      else if (trimmed.rfind("xmax =", 0) == 0)
        current.endSeconds = std::stod(valueOf(trimmed));
    } catch (const std::exception&) {
      throw fileError(textGrid, "has a time that is not a number: " + trimmed);
    }
    if (trimmed.rfind("text =", 0) == 0) {
      std::string label = valueOf(trimmed);
      if (label.size() >= 2 && label.front() == '"' && label.back() == '"') label = label.substr(1, label.size() - 2);
      while (!label.empty() && std::isdigit(static_cast<unsigned char>(label.back()))) label.pop_back();  // stress
      current.label = label.empty() ? "SIL" : upper(label);
      phones.push_back(current);
    }
  }
  if (phones.empty()) throw fileError(textGrid, "has no \"phones\" tier with intervals");
  return phones;
}

PhoneClass phoneClassOf(const std::string& arpabet) {
  static const std::set<std::string> silence{"SIL", "SP", "SPN", "NSN", ""};
  static const std::set<std::string> bilabial{"P", "B", "M"};
  static const std::set<std::string> labiodental{"F", "V"};
  static const std::set<std::string> open{"AA", "AE", "AW", "AY"};
  static const std::set<std::string> rounded{"UW", "UH", "OW", "OY", "AO", "W"};
  static const std::set<std::string> spread{"IY", "IH", "EY"};
  static const std::set<std::string> otherVowel{"AH", "EH", "ER"};
  if (silence.count(arpabet)) return PhoneClass::kSilence;
  if (bilabial.count(arpabet)) return PhoneClass::kBilabial;
  if (labiodental.count(arpabet)) return PhoneClass::kLabiodental;
  if (open.count(arpabet)) return PhoneClass::kOpenVowel;
  if (rounded.count(arpabet)) return PhoneClass::kRoundedVowel;
  if (spread.count(arpabet)) return PhoneClass::kSpreadVowel;
  if (otherVowel.count(arpabet)) return PhoneClass::kOtherVowel;
  return PhoneClass::kConsonant;
}

const char* phoneClassName(PhoneClass phoneClass) {
  switch (phoneClass) {
    case PhoneClass::kSilence:
      return "silence";
    case PhoneClass::kBilabial:
      return "bilabial /p b m/";
    case PhoneClass::kLabiodental:
      return "labiodental /f v/";
    case PhoneClass::kOpenVowel:
      return "open vowel";
    case PhoneClass::kRoundedVowel:
      return "rounded /u o w/";
    case PhoneClass::kSpreadVowel:
      return "spread /i/";
    case PhoneClass::kOtherVowel:
      return "other vowel";
    case PhoneClass::kConsonant:
      return "consonant";
  }
  return "?";
}

std::vector<PhoneClass> labelClassesAt(const std::vector<LabelInterval>& labels, bool labelsAreWords,
                                       double framesPerSecond, Eigen::Index frames) {
  // GRID's vocabulary: the words that open with a bilabial, and those whose vowel is open (/æ aɪ aʊ ɑ/).
  static const std::set<std::string> bilabialStart{"bin", "place", "blue", "by", "please", "b", "p"};
  static const std::set<std::string> openVowel{"at", "now", "white", "by", "i", "five", "nine", "r", "y"};
  std::vector<PhoneClass> classes(static_cast<std::size_t>(frames), PhoneClass::kConsonant);
  std::size_t at = 0;
  for (Eigen::Index i = 0; i < frames; ++i) {
    const double t = static_cast<double>(i) / framesPerSecond;
    while (at < labels.size() && labels[at].endSeconds <= t) ++at;
    if (at >= labels.size() || labels[at].startSeconds > t) {
      if (labels.empty() || t >= labels.back().endSeconds || t < labels.front().startSeconds)
        classes[static_cast<std::size_t>(i)] = PhoneClass::kSilence;
      continue;
    }
    const LabelInterval& label = labels[at];
    PhoneClass& out = classes[static_cast<std::size_t>(i)];
    if (!labelsAreWords) {
      out = phoneClassOf(label.label);
      continue;
    }
    const double into = t - label.startSeconds;
    const double length = label.endSeconds - label.startSeconds;
    if (label.label == "sil" || label.label == "sp")
      out = PhoneClass::kSilence;
    else if (bilabialStart.count(label.label) && into < 0.080)
      out = PhoneClass::kBilabial;
    else if (openVowel.count(label.label) && into >= length / 3.0 && into < 2.0 * length / 3.0 &&
             (!bilabialStart.count(label.label) || into >= 0.080))
      out = PhoneClass::kOpenVowel;
  }
  return classes;
}

}  // namespace th::eval
