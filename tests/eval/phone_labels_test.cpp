// Phones from words: GRID's lexicon, the Arabic letters read as phones, words placed in time, frames classed.
#include "eval/phone_labels.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/data_path.h"
#include "core/error.h"
#include "core/temporary_file.h"
#include "face/visemes.h"

namespace {

using th::eval::LabelInterval;
using Phones = std::vector<std::string>;

TEST(PhoneLabels, GridWordsHaveTheirDictionaryPhones) {
  EXPECT_EQ(th::eval::gridPronunciation("bin"), (Phones{"B", "IH", "N"}));
  EXPECT_EQ(th::eval::gridPronunciation("Please"), (Phones{"P", "L", "IY", "Z"}));
  EXPECT_EQ(th::eval::gridPronunciation("w"), Phones{});  // GRID has no letter w
  // Every word of every shared GRID alignment is in the vocabulary.
  for (const auto& entry : std::filesystem::directory_iterator(th::sharedDataPath("grid/s1"))) {
    if (entry.path().extension() == ".align") {
      EXPECT_NO_THROW(th::eval::gridPhones(th::eval::readGridAlignment(entry.path())));
    }
  }
}

TEST(PhoneLabels, AWordsPhonesShareItsIntervalAndStartWithIt) {
  const std::vector<LabelInterval> phones =
      th::eval::gridPhones({{0.0, 0.2, "sil"}, {0.2, 0.5, "bin"}, {0.5, 0.6, "sp"}});
  ASSERT_EQ(phones.size(), 5u);
  EXPECT_EQ(phones[0].label, "SIL");
  EXPECT_EQ(phones[1].label, "B");
  EXPECT_DOUBLE_EQ(phones[1].startSeconds, 0.2);
  EXPECT_DOUBLE_EQ(phones[3].endSeconds, 0.5);
  // B : IH : N = 0.9 : 0.9 : 0.8 of the word's 300 ms.
  EXPECT_NEAR(phones[1].endSeconds - phones[1].startSeconds, 0.3 * 0.9 / 2.6, 1e-12);
  EXPECT_THROW(th::eval::gridPhones({{0.0, 0.3, "banana"}}), th::Error);
}

TEST(PhoneLabels, ArabicLettersBecomePhones) {
  // qāla "he said": the alef lengthens the fatha.
  EXPECT_EQ(th::eval::arabicPronunciation("قَالَ"), (Phones{"K", "AA", "L", "AH"}));
  // fī "in": the yeh after an unmarked consonant is a long i.
  EXPECT_EQ(th::eval::arabicPronunciation("في"), (Phones{"F", "IY"}));
  // ʔuṣība "was injured", after the conjunction wa written apart.
  EXPECT_EQ(th::eval::arabicPronunciation("و أُصيبَ"), (Phones{"W", "HH", "UH", "S", "IY", "B", "AH"}));
  // as-salām: the article's lam is silent before the sun letter sin, which is doubled; the unwritten vowel
  // after it is a slot of its own.
  EXPECT_EQ(th::eval::arabicPronunciation("السلام"), (Phones{"?", "S", "S", "?", "L", "AA", "M"}));
  // min "from": an unwritten vowel between two consonants, none after the last.
  EXPECT_EQ(th::eval::arabicPronunciation("من"), (Phones{"M", "?", "N"}));
  // al-yaman: a moon letter keeps the lam.
  EXPECT_EQ(th::eval::arabicPronunciation("اليَمن"), (Phones{"?", "L", "Y", "AH", "M", "?", "N"}));
  // Tanwin adds an n; a final teh marbuta is the pausal -a.
  EXPECT_EQ(th::eval::arabicPronunciation("كِتَابٌ"), (Phones{"K", "IH", "T", "AA", "B", "UH", "N"}));
  EXPECT_EQ(th::eval::arabicPronunciation("قُوَّة"), (Phones{"K", "UH", "W", "W", "AH", "AH"}));
  // The mouth classes of the lips' letters: b and m close the lips, f is labiodental, w rounds them.
  EXPECT_EQ(th::face::mouthClassOfPhone("B"), th::face::kPp);
  EXPECT_EQ(th::face::mouthClassOfPhone("?"), -1);
}

TEST(PhoneLabels, NewsClipsWordTimingsAreReadAndUnplacedWordsLeftOut) {
  th::TemporaryFile csv(".words.csv");
  {
    std::ofstream out(csv.path());
    out << "conf,end,start,word\r\n,,,قد\r\n1.0,0.48,0.03,قَالَ\r\n0.9,0.66,0.48,إنَ\r\n";
  }
  const std::vector<LabelInterval> words = th::eval::readWordTimings(csv.path());
  ASSERT_EQ(words.size(), 2u);
  EXPECT_DOUBLE_EQ(words[0].startSeconds, 0.03);
  EXPECT_DOUBLE_EQ(words[1].endSeconds, 0.66);
  const std::vector<LabelInterval> phones = th::eval::arabicPhones(words);
  ASSERT_EQ(phones.size(), 8u);  // K AA L AH, HH IH N AH
  EXPECT_EQ(phones.front().label, "K");
  EXPECT_DOUBLE_EQ(phones.front().startSeconds, 0.03);
  EXPECT_DOUBLE_EQ(phones.back().endSeconds, 0.66);
  const std::vector<int> classes = th::eval::mouthClassesAt(phones, 30.0, 25);
  EXPECT_EQ(classes[0], -1);             // 0 s: before the first placed word
  EXPECT_EQ(classes[2], th::face::kKk);  // 67 ms: the q
  EXPECT_EQ(classes[24], -1);            // 0.8 s: after the last word

  th::TemporaryFile bad(".words.csv");
  {
    std::ofstream out(bad.path());
    out << "conf,end,start,word\n1.0,0.2,0.5,x\n";
  }
  try {
    th::eval::readWordTimings(bad.path());
    FAIL() << "an end before its start was accepted";
  } catch (const th::Error& error) {
    EXPECT_NE(std::string(error.what()).find(bad.path().string() + ": line 2"), std::string::npos) << error.what();
  }
}

TEST(PhoneLabels, EveryNewsClipsWordsGivePhones) {
  const std::filesystem::path folder = th::sharedDataPath("talking/arabic-news");
  int clips = 0, bilabials = 0, phones = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (name.size() < 10 || name.substr(name.size() - 10) != ".words.csv") continue;
    ++clips;
    for (const LabelInterval& phone : th::eval::arabicPhones(th::eval::readWordTimings(entry.path()))) {
      ++phones;
      bilabials += th::face::mouthClassOfPhone(phone.label) == th::face::kPp ? 1 : 0;
    }
  }
  EXPECT_EQ(clips, 972);
  // b and m are about a tenth of the letters said (998 + 406 of some 13,000 letters and marks).
  EXPECT_GT(bilabials, 1000);
  EXPECT_LT(bilabials, phones / 5);
}

}  // namespace
