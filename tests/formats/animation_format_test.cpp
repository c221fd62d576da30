// Animation files: CSV and JSON round trips are exact and .fap round trips are exact to integer rounding; a
// .fap whose masks change reads back with the FAPs that are not sent holding their values; every bad file is
// refused with one line naming the file, the line (CSV, .fap) and the problem; a failed write leaves nothing.
#include "formats/animation_format.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "core/error.h"
#include "core/temporary_file.h"
#include "support/files.h"

namespace th::formats {
namespace {

using th::test::expectFileError;
using th::test::listFolder;
using th::test::readText;

namespace fs = std::filesystem;
using Animation = face::FapTrack;

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// A mask line: 68 flags, 1 for the FAPs given.
std::string maskLine(std::initializer_list<int> faps) {
  std::string line;
  for (int fap = 1; fap <= 68; ++fap) {
    line += fap > 1 ? " " : "";
    line += std::find(faps.begin(), faps.end(), fap) != faps.end() ? '1' : '0';
  }
  return line;
}

Animation randomAnimation(double fps, int numFrames, std::vector<int> faps, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> value(-600.0, 600.0);
  Animation animation{
      .framesPerSecond = fps, .name = "round trip", .faps = std::move(faps), .values = {}, .visemes = {}, .source = {}};
  animation.values.resize(static_cast<Eigen::Index>(animation.faps.size()), numFrames);
  for (Eigen::Index i = 0; i < animation.values.size(); ++i) animation.values.data()[i] = value(random);
  return animation;
}

std::string readError(const fs::path& path) {
  try {
    readAnimation(path);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

std::string writeError(const fs::path& path, const Animation& animation) {
  try {
    writeAnimation(path, animation);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// ---- round trips ----

class AnimationRoundTrip : public ::testing::TestWithParam<std::tuple<std::string, double>> {};

TEST_P(AnimationRoundTrip, ReadsBackWhatWasWritten) {
  const auto& [extension, fps] = GetParam();
  TemporaryFolder folder;
  const Animation written = randomAnimation(fps, 97, {3, 4, 5, 12, 19, 31, 48, 49, 50, 68}, 11);
  const fs::path path = folder.path() / ("animation" + extension);
  writeAnimation(path, written);
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{path.filename().string()});

  const Animation back = readAnimation(path);
  EXPECT_EQ(back.framesPerSecond, fps);
  EXPECT_EQ(back.faps, written.faps);
  ASSERT_EQ(back.numFrames(), written.numFrames());
  ASSERT_EQ(back.values.cols(), written.values.cols());
  if (extension == ".fap") {
    // std::round and the writer's std::lround both round halves away from zero.
    EXPECT_TRUE(back.values == written.values.array().round().matrix());
    EXPECT_EQ(back.name, "round_trip");
  } else {
    EXPECT_TRUE(back.values == written.values)
        << "largest difference " << (back.values - written.values).cwiseAbs().maxCoeff();
    EXPECT_EQ(back.name, extension == ".json" ? "round trip" : Animation{}.name);  // CSV has no name
  }
}

INSTANTIATE_TEST_SUITE_P(Formats, AnimationRoundTrip,
                         ::testing::Combine(::testing::Values(".csv", ".json", ".fap"), ::testing::Values(25.0, 30.0)));

TEST(AnimationFile, FractionalRatesRoundTrip) {
  TemporaryFolder folder;
  for (const double fps : {30000.0 / 1001.0, 12.5, 7.3}) {
    for (const std::string extension : {".csv", ".json", ".fap"}) {
      const Animation written = randomAnimation(fps, 40, {3, 48}, 5);
      const fs::path path = folder.path() / ("rate" + extension);
      writeAnimation(path, written);
      const Animation back = readAnimation(path);
      EXPECT_EQ(back.framesPerSecond, fps) << extension;
    }
  }
}

TEST(AnimationFile, ExtensionIsCaseInsensitive) {
  TemporaryFolder folder;
  const Animation written = randomAnimation(25, 3, {3}, 1);
  writeAnimation(folder.path() / "upper.FAP", written);
  EXPECT_EQ(readAnimation(folder.path() / "upper.FAP").numFrames(), 3);
  EXPECT_EQ(animationFormatFor("a.Json").name(), "json");
  EXPECT_EQ(animationFormatFor("dir.fap/a.CSV").name(), "csv");
}

TEST(AnimationFile, RowOf) {
  const Animation animation{.faps = {3, 48, 50}, .values = {}, .visemes = {}, .source = {}};
  EXPECT_EQ(animation.rowOf(3), 0);
  EXPECT_EQ(animation.rowOf(50), 2);
  EXPECT_EQ(animation.rowOf(4), -1);
  EXPECT_EQ(animation.rowOf(0), -1);
}

// ---- what is written ----

Animation smallAnimation() {
  Animation animation{
      .framesPerSecond = 25, .name = "hello world", .faps = {3, 48}, .values = {}, .visemes = {}, .source = {}};
  animation.values = (Eigen::MatrixXd(2, 2) << 10.4, 11.6, -2.5, 0.0).finished();  // a column per frame
  return animation;
}

TEST(AnimationFile, WritesFapStreamText) {
  TemporaryFolder folder;
  writeAnimation(folder.path() / "small.fap", smallAnimation());
  const std::string mask = maskLine({3, 48});
  EXPECT_EQ(readText(folder.path() / "small.fap"),
            "2.1 hello_world 25 2\n" + mask + "\n0 10 -3\n" + mask + "\n1 12 0\n");
}

TEST(AnimationFile, WritesCsvText) {
  TemporaryFolder folder;
  writeAnimation(folder.path() / "small.csv", smallAnimation());
  EXPECT_EQ(readText(folder.path() / "small.csv"), "time_s,fap3,fap48\n0.0000000,10.4,-2.5\n0.0400000,11.6,0\n");
}

TEST(AnimationFile, WritesJsonDocument) {
  TemporaryFolder folder;
  writeAnimation(folder.path() / "small.json", smallAnimation());
  const auto document = nlohmann::json::parse(readText(folder.path() / "small.json"));
  EXPECT_EQ(document.at("format"), "talkinghead-animation");
  EXPECT_EQ(document.at("version"), 1);
  EXPECT_EQ(document.at("fps"), 25.0);
  EXPECT_EQ(document.at("name"), "hello world");
  EXPECT_EQ(document.at("faps").at(0), (nlohmann::json{{"number", 3}, {"name", "open_jaw"}, {"unit", "MNS"}}));
  EXPECT_EQ(document.at("faps").at(1), (nlohmann::json{{"number", 48}, {"name", "head_pitch"}, {"unit", "AU"}}));
  EXPECT_EQ(document.at("time_s"), (nlohmann::json{0.0, 0.04}));
  ASSERT_TRUE(document.at("frames").at(1).at(0).is_number());
  EXPECT_EQ(document.at("frames"), (nlohmann::json{{10.4, -2.5}, {11.6, 0.0}}));
}

// ---- reading what others write ----

TEST(AnimationFile, FapMasksMayChangeAndUnsentFapsHoldTheirValues) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "holds.fap";
  writeText(path,
            "# a hand-written stream\n"
            "2.1 holds 25 5\n" +
                maskLine({3}) + "\n1 100\n\n" +          // FAP 48 not yet sent: 0
                maskLine({3, 48}) + "\n2 110 -2000\n" +  //
                "# FAP 3 holds 110\n" + maskLine({48}) + "\n3 -1000\n" + maskLine({}) +
                "\n7\n" +  // nothing sent: both hold; frame numbers may skip
                maskLine({3}) + "\n8 -5\n");
  const Animation animation = readAnimation(path);
  EXPECT_EQ(animation.name, "holds");
  EXPECT_EQ(animation.framesPerSecond, 25.0);
  EXPECT_EQ(animation.faps, (std::vector<int>{3, 48}));
  Eigen::MatrixXd expected(2, 5);
  expected << 100, 110, 110, 110, -5, 0, -2000, -1000, -1000, -1000;
  EXPECT_TRUE(animation.values == expected) << animation.values;
}

TEST(AnimationFile, ReadsXfaceStyleStream) {
  // As Xface's tools save them: CRLF line ends, a trailing space, the audio file's name as NAME, frames from
  // 0.
  const std::string mask =
      "0 0 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 0 0 0 0 0 0 0 0 1 1 1 1 1 1 1 1 0 0 0 0 0 0 0 0 0 1 1 1 1 "
      "1 1 1 1 "
      "1 1 1 1 1 0 0 0 0 0 0 0 0 \r\n";
  const std::string text = "2.1 C:\\Xface\\samples\\hello.wav 25 3 \r\n" + mask +
                           "0 -57 257 -167 78 185 294 -233 -287 180 -35 264 -61 -104 181 253 262 187 106 "
                           "-146 -63 -145 235 99 -285 -235 "
                           "-137 -257 8 -269 -25 184 96 137 104 290 155 -163 74 -201 -264 -161 \r\n" +
                           mask +
                           "1 206 -78 -36 146 8 131 219 95 287 59 246 299 117 298 -63 44 -271 -14 -133 34 "
                           "254 285 282 -194 -84 287 -27 "
                           "-9 -173 -236 193 195 -210 52 -232 120 -146 -280 0 137 125 \r\n" +
                           mask +
                           "2 -179 -255 -254 86 300 38 264 -15 217 -59 -264 17 -293 -222 -190 248 -268 -98 "
                           "117 -2 -31 -141 -257 47 21 68 "
                           "-159 86 85 171 232 95 272 -195 219 -23 141 -57 8 147 -36 \r\n";
  TemporaryFolder folder;
  const fs::path path = folder.path() / "hello.fap";
  writeText(path, text);
  const Animation animation = readAnimation(path);
  EXPECT_EQ(animation.name, "C:\\Xface\\samples\\hello.wav");
  EXPECT_EQ(animation.framesPerSecond, 25.0);
  ASSERT_EQ(animation.numFrames(), 3);
  std::vector<int> faps;
  for (int fap = 3; fap <= 22; ++fap) faps.push_back(fap);
  for (int fap = 31; fap <= 38; ++fap) faps.push_back(fap);
  for (int fap = 48; fap <= 60; ++fap) faps.push_back(fap);
  EXPECT_EQ(animation.faps, faps);
  const int jaw = animation.rowOf(3);
  const int headYaw = animation.rowOf(49);
  const int lastLip = animation.rowOf(60);
  EXPECT_EQ(animation.values(jaw, 0), -57);
  EXPECT_EQ(animation.values(jaw, 2), -179);
  EXPECT_EQ(animation.values(headYaw, 1), -236);
  EXPECT_EQ(animation.values(lastLip, 0), -161);
  EXPECT_EQ(animation.values(lastLip, 2), -36);
}

TEST(AnimationFile, CsvColumnsInAnyOrderAndTimesWithinTolerance) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "hand.csv";
  // Columns out of order, spaces, CRLF, a start other than 0, and jitter well inside 1e-4 of a frame.
  writeText(path, "time_s, fap48 ,fap3\r\n\r\n5.00,1,2\r\n5.040000001,3,4\r\n5.08,5,6\r\n");
  const Animation animation = readAnimation(path);
  EXPECT_EQ(animation.framesPerSecond, 25.0);
  EXPECT_EQ(animation.faps, (std::vector<int>{3, 48}));
  Eigen::MatrixXd expected(2, 3);
  expected << 2, 4, 6, 1, 3, 5;
  EXPECT_TRUE(animation.values == expected) << animation.values;
}

// ---- bad input ----

struct BadFile {
  std::string label;
  std::string extension;
  std::string text;
  std::string problem;  // expected in the message
};

std::vector<BadFile> badFiles() {
  const std::string m0 = maskLine({});
  const std::string m3 = maskLine({3});
  const std::string m3and48 = maskLine({3, 48});
  const std::string json = R"({"format": "talkinghead-animation", "version": 1, "fps": 25, )";
  return {
      // CSV
      {"CsvEmpty", ".csv", "", "is empty"},
      {"CsvBlank", ".csv", "\n  \r\n", "is empty"},
      {"CsvNoHeader", ".csv", "0,1\n0.04,2\n", "line 1: the header is missing"},
      {"CsvFirstColumnNotTime", ".csv", "time,fap3\n0,1\n0.04,2\n", "line 1: the first column is 'time'"},
      {"CsvFap69", ".csv", "time_s,fap69\n0,1\n0.04,2\n", "line 1: column 2 'fap69' is not a FAP column"},
      {"CsvFap0", ".csv", "time_s,fap0\n0,1\n0.04,2\n", "line 1: column 2 'fap0' is not a FAP column"},
      {"CsvNotFap", ".csv", "time_s,fap3,jaw\n0,1,2\n0.04,2,3\n", "line 1: column 3 'jaw' is not a FAP column"},
      {"CsvEmptyColumnName", ".csv", "time_s,\n0,1\n", "line 1: column 2 '' is not a FAP column"},
      {"CsvDuplicate", ".csv", "time_s,fap3,fap48,fap3\n0,1,2,3\n", "line 1: columns 2 and 4 are both fap3"},
      {"CsvTooManyValues", ".csv", "time_s,fap3\n0,1\n0.04,1,2\n", "line 3: 3 values, but the header has 2 columns"},
      {"CsvTooFewValues", ".csv", "time_s,fap3\n\n0\n", "line 3: 1 value, but the header has 2 columns"},
      {"CsvText", ".csv", "time_s,fap3\n0,1\n0.04,abc\n", "line 3: fap3 'abc' is not a finite number"},
      {"CsvNan", ".csv", "time_s,fap3\n0,nan\n0.04,1\n", "line 2: fap3 'nan' is not a finite number"},
      {"CsvInf", ".csv", "time_s,fap3\n0,1\n0.04,-inf\n", "line 3: fap3 '-inf' is not a finite number"},
      {"CsvOverflow", ".csv", "time_s,fap3\n0,1\n0.04,1e999\n", "line 3: fap3 '1e999' is not a finite number"},
      {"CsvEmptyValue", ".csv", "time_s,fap3\n0,\n", "line 2: fap3 '' is not a finite number"},
      {"CsvTimeText", ".csv", "time_s,fap3\nzero,1\n", "line 2: time_s 'zero' is not a finite number"},
      {"CsvNoFrames", ".csv", "time_s,fap3\n", "line 1: no frames follow the header"},
      {"CsvOneFrame", ".csv", "time_s,fap3\n0,1\n", "line 2: one frame: the frame rate cannot be derived from time_s"},
      {"CsvUneven", ".csv", "time_s,fap3\n0,1\n0.04,1\n0.1,1\n0.12,1\n",
       "line 4: time_s 0.1 breaks the even spacing of frames"},
      {"CsvJustOutsideTolerance", ".csv", "time_s,fap3\n0,1\n0.040005,1\n0.08,1\n",
       "line 3: time_s 0.040005 breaks the even spacing"},
      {"CsvSameTimes", ".csv", "time_s,fap3\n0,1\n0,1\n", "line 3: time_s 0 is not after the first row's 0"},
      {"CsvDecreasing", ".csv", "time_s,fap3\n1,1\n0.5,1\n0,1\n", "line 4: time_s 0 is not after the first row's 1"},
      // .fap
      {"FapEmpty", ".fap", "", "is empty"},
      {"FapOnlyComments", ".fap", "# nothing\n\n", "is empty"},
      {"FapNoHeader", ".fap", m3 + "\n0 1\n", "line 1: the header `2.1 NAME FPS NFRAMES` is missing"},
      {"FapShortHeader", ".fap", "2.1 name 25\n", "line 1: the header `2.1 NAME FPS NFRAMES` is missing"},
      {"FapVersion", ".fap", "2.0 name 25 1\n" + m3 + "\n0 1\n", "line 1: version '2.0' is not 2.1"},
      {"FapZeroFps", ".fap", "2.1 name 0 1\n" + m3 + "\n0 1\n", "line 1: the frame rate '0' is not a positive"},
      {"FapNegativeFps", ".fap", "2.1 name -25 1\n" + m3 + "\n0 1\n", "line 1: the frame rate '-25' is not"},
      {"FapNanFps", ".fap", "2.1 name nan 1\n" + m3 + "\n0 1\n", "line 1: the frame rate 'nan' is not"},
      {"FapTextFps", ".fap", "2.1 name fast 1\n" + m3 + "\n0 1\n", "line 1: the frame rate 'fast' is not"},
      {"FapNegativeCount", ".fap", "2.1 name 25 -1\n" + m3 + "\n0 1\n", "line 1: the frame count '-1' is not"},
      {"FapCountBeyondInt64", ".fap", "2.1 name 25 99999999999999999999999\n" + m3 + "\n0 1\n",
       "line 1: the frame count '99999999999999999999999' is not a whole number"},
      {"FapHugeCount", ".fap", "2.1 name 25 999999999999999999\n" + m3 + "\n0 1\n",
       "line 1: the header announces 999999999999999999 frames, but the file has 1"},
      {"FapFewerFrames", ".fap", "2.1 name 25 3\n" + m3 + "\n0 1\n" + m3 + "\n1 1\n",
       "line 1: the header announces 3 frames, but the file has 2"},
      {"FapMoreFrames", ".fap", "2.1 name 25 1\n" + m3 + "\n0 1\n" + m3 + "\n1 1\n",
       "line 4: a frame beyond the 1 that the header on line 1 announces"},
      {"FapNoFrames", ".fap", "2.1 name 25 0\n", "line 1: no frames follow the header"},
      {"FapShortMask", ".fap", "2.1 name 25 1\n0 0 1\n0 1\n", "line 2: the mask has 3 flags; expected 68"},
      {"FapLongMask", ".fap", "2.1 name 25 1\n" + m3 + " 0\n0 1\n", "line 2: the mask has 69 flags; expected 68"},
      {"FapFlagNotBinary", ".fap", "2.1 name 25 1\n" + std::string("0 0 2") + m3.substr(5) + "\n0 1\n",
       "line 2: mask flag 3 is '2'; expected 0 or 1"},
      {"FapFlagText", ".fap", "2.1 name 25 1\nx" + m3.substr(1) + "\n0 1\n",
       "line 2: mask flag 1 is 'x'; expected 0 or 1"},
      {"FapTooFewValues", ".fap", "2.1 name 25 1\n" + m3and48 + "\n0 1\n",
       "line 3: the frame number is followed by 1 value, but the mask on line 2 flags 2 FAPs"},
      {"FapTooManyValues", ".fap", "2.1 name 25 1\n" + m0 + "\n0 1\n",
       "line 3: the frame number is followed by 1 value, but the mask on line 2 flags 0 FAPs"},
      {"FapFractionalValue", ".fap", "2.1 name 25 1\n" + m3and48 + "\n0 1 2.5\n",
       "line 3: fap48 '2.5' is not a 32-bit integer"},
      {"FapValueBeyondInt32", ".fap", "2.1 name 25 1\n" + m3 + "\n0 2147483648\n",
       "line 3: fap3 '2147483648' is not a 32-bit integer"},
      {"FapMissingValueLine", ".fap", "2.1 name 25 1\n" + m3 + "\n\n# gone\n", "line 2: the file ends after this mask"},
      {"FapRepeatedFrameNumber", ".fap", "2.1 name 25 2\n" + m3 + "\n0 1\n" + m3 + "\n0 2\n",
       "line 5: frame number 0 follows 0: frame numbers must increase"},
      {"FapDecreasingFrameNumber", ".fap", "2.1 name 25 2\n" + m3 + "\n5 1\n" + m3 + "\n3 2\n",
       "line 5: frame number 3 follows 5"},
      {"FapNegativeFrameNumber", ".fap", "2.1 name 25 1\n" + m3 + "\n-1 1\n",
       "line 3: the frame number '-1' is not a whole number"},
      // JSON
      {"JsonEmpty", ".json", " \n", "is empty"},
      {"JsonSyntax", ".json", "{\"format\": ", "is not valid JSON"},
      {"JsonArray", ".json", "[1, 2]", "holds an array, not an animation object"},
      {"JsonTooDeep", ".json", json + R"("faps": [], "frames": [[[[[[[[[[1]]]]]]]]]]})", "nests arrays"},
      {"JsonMissingFormat", ".json", R"({"version": 1, "fps": 25, "faps": [], "frames": [[]]})", "format is missing"},
      {"JsonWrongFormat", ".json", R"({"format": "talkinghead-hmm", "version": 1})",
       "format is \"talkinghead-hmm\", not \"talkinghead-animation\""},
      {"JsonVersion", ".json", R"({"format": "talkinghead-animation", "version": 2})",
       "version is 2; this program reads version 1"},
      {"JsonFloatVersion", ".json", R"({"format": "talkinghead-animation", "version": 1.0})", "version is 1.0"},
      {"JsonMissingFps", ".json", R"({"format": "talkinghead-animation", "version": 1, "faps": [], "frames": [[]]})",
       "fps is missing"},
      {"JsonFpsString", ".json", json.substr(0, json.find("25")) + R"("25", "faps": [], "frames": [[]]})",
       "fps is \"25\", not a number"},
      {"JsonZeroFps", ".json", json.substr(0, json.find("25")) + R"(0, "faps": [], "frames": [[]]})",
       "fps is 0; it must be positive"},
      {"JsonNegativeFps", ".json", json.substr(0, json.find("25")) + R"(-30, "faps": [], "frames": [[]]})",
       "fps is -30; it must be positive"},
      {"JsonMissingFaps", ".json", json + R"("frames": [[]]})", "faps is missing"},
      {"JsonMissingFrames", ".json", json + R"("faps": []})", "frames is missing"},
      {"JsonFramesNotArray", ".json", json + R"("faps": [], "frames": {}})", "frames is an object, not an array"},
      {"JsonNoFrames", ".json", json + R"("faps": [], "frames": []})", "frames is empty: no frames"},
      {"JsonUnknownField", ".json", json + R"("faps": [], "frames": [[]], "framez": 1})",
       "framez is not a known field"},
      {"JsonNameNotString", ".json", json + R"("name": 5, "faps": [], "frames": [[]]})",
       "name is an integer, not a string"},
      {"JsonFapNotObject", ".json", json + R"("faps": [3], "frames": [[1]]})", "faps[0] is an integer, not an object"},
      {"JsonFapNumberMissing", ".json", json + R"("faps": [{"name": "open_jaw"}], "frames": [[1]]})",
       "faps[0].number is missing"},
      {"JsonUnknownFap", ".json", json + R"("faps": [{"number": 3}, {"number": 69}], "frames": [[1, 2]]})",
       "faps[1].number is 69, not a FAP number (1..68)"},
      {"JsonFapZero", ".json", json + R"("faps": [{"number": 0}], "frames": [[1]]})",
       "faps[0].number is 0, not a FAP number"},
      {"JsonFapNegative", ".json", json + R"("faps": [{"number": -3}], "frames": [[1]]})",
       "faps[0].number is -3, not a FAP number"},
      {"JsonFapFloat", ".json", json + R"("faps": [{"number": 3.0}], "frames": [[1]]})",
       "faps[0].number is 3.0, not an integer"},
      {"JsonFapString", ".json", json + R"("faps": [{"number": "3"}], "frames": [[1]]})",
       "faps[0].number is \"3\", not a FAP number"},
      {"JsonFapsDescending", ".json", json + R"("faps": [{"number": 48}, {"number": 3}], "frames": [[1, 2]]})",
       "faps[1].number is 3, after 48: the FAP numbers must be ascending and unique"},
      {"JsonFapsDuplicate", ".json", json + R"("faps": [{"number": 3}, {"number": 3}], "frames": [[1, 2]]})",
       "faps[1].number is 3, after 3"},
      {"JsonFapNameDisagrees", ".json", json + R"("faps": [{"number": 3, "name": "head_yaw"}], "frames": [[1]]})",
       "faps[0].name is \"head_yaw\", but FAP 3 is \"open_jaw\""},
      {"JsonFapUnitDisagrees", ".json", json + R"("faps": [{"number": 3, "unit": "AU"}], "frames": [[1]]})",
       "faps[0].unit is \"AU\", but FAP 3 is in \"MNS\""},
      {"JsonFapUnknownField", ".json", json + R"("faps": [{"number": 3, "scale": 2}], "frames": [[1]]})",
       "faps[0].scale is not a known field"},
      {"JsonRowTooShort", ".json", json + R"("faps": [{"number": 3}, {"number": 48}], "frames": [[1, 2], [3]]})",
       "frames[1] has 1 value, but faps lists 2 FAPs"},
      {"JsonRowTooLong", ".json", json + R"("faps": [{"number": 3}], "frames": [[1, 2]]})",
       "frames[0] has 2 values, but faps lists 1 FAP"},
      {"JsonRowNotArray", ".json", json + R"("faps": [{"number": 3}], "frames": [1]})",
       "frames[0] is an integer, not an array"},
      {"JsonNullValue", ".json", json + R"("faps": [{"number": 3}], "frames": [[1], [null]]})",
       "frames[1][0] is null, not a number"},
      {"JsonStringValue", ".json", json + R"("faps": [{"number": 3}], "frames": [["1"]]})",
       "frames[0][0] is \"1\", not a number"},
      {"JsonOverflow", ".json", json + R"("faps": [{"number": 3}], "frames": [[1e999]]})",
       "is out of the range of a double"},
      {"JsonNan", ".json", json + R"("faps": [{"number": 3}], "frames": [[NaN]]})", "is not valid JSON"},
      {"JsonTimesWrongLength", ".json", json + R"("faps": [], "time_s": [0], "frames": [[], []]})",
       "time_s has 1 time, but there are 2 frames"},
      {"JsonTimesDisagree", ".json", json + R"("faps": [], "time_s": [0, 0.04, 0.5], "frames": [[], [], []]})",
       "time_s[2] is 0.5, but at 25 fps frame 2 is at 0.08"},
  };
}

class BadAnimationFile : public ::testing::TestWithParam<BadFile> {};

TEST_P(BadAnimationFile, IsRefusedWithOneLineNamingFileAndProblem) {
  const BadFile& bad = GetParam();
  TemporaryFolder folder;
  const fs::path path = folder.path() / ("bad" + bad.extension);
  writeText(path, bad.text);
  expectFileError(readError(path), path, bad.problem);
}

INSTANTIATE_TEST_SUITE_P(Cases, BadAnimationFile, ::testing::ValuesIn(badFiles()),
                         [](const ::testing::TestParamInfo<BadFile>& testInfo) { return testInfo.param.label; });

TEST(AnimationFile, DirectoryIsRefused) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "folder.fap";
  fs::create_directory(path);
  expectFileError(readError(path), path, "is a directory");
}

TEST(AnimationFile, MissingFileIsRefused) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "missing.csv";
  expectFileError(readError(path), path, "does not exist");
  expectFileError(readError(folder.path() / "missing" / "a.json"), folder.path() / "missing" / "a.json",
                  "does not exist");
}

TEST(AnimationFile, UnknownExtensionIsRefused) {
  TemporaryFolder folder;
  const fs::path text = folder.path() / "animation.txt";
  writeText(text, "time_s,fap3\n0,1\n0.04,2\n");
  expectFileError(readError(text), text, "has the extension '.txt'; an animation file is .csv, .json or .fap");
  const fs::path none = folder.path() / "animation";
  expectFileError(writeError(none, randomAnimation(25, 2, {3}, 1)), none, "has no extension");
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{"animation.txt"});
}

// ---- failed writes ----

TEST(AnimationFile, WriteToMissingFolderLeavesNothing) {
  TemporaryFolder folder;
  const Animation animation = randomAnimation(25, 4, {3}, 2);
  const fs::path missing = folder.path() / "missing" / "a.fap";
  expectFileError(writeError(missing, animation), missing, "does not exist");
  writeText(folder.path() / "plain", "a file, not a folder");
  const fs::path underFile = folder.path() / "plain" / "a.csv";
  expectFileError(writeError(underFile, animation), underFile, "does not exist");
  const fs::path directory = folder.path() / "taken.json";
  fs::create_directory(directory);
  expectFileError(writeError(directory, animation), directory, "is a directory");
  EXPECT_EQ(listFolder(folder.path()), (std::vector<std::string>{"plain", "taken.json"}));
  EXPECT_TRUE(fs::is_empty(directory));
}

struct BadAnimation {
  std::string label;
  std::string extension;
  Animation animation;
  std::string problem;
};

std::vector<BadAnimation> badAnimations() {
  const Animation good = randomAnimation(25, 4, {3, 48}, 3);
  auto with = [&](auto change) {
    Animation animation = good;
    change(animation);
    return animation;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  return {
      {"ZeroFps", ".fap", with([](Animation& a) { a.framesPerSecond = 0; }), "the frame rate 0 fps is not positive"},
      {"NegativeFps", ".csv", with([](Animation& a) { a.framesPerSecond = -25; }), "the frame rate -25 fps"},
      {"NanFps", ".json", with([&](Animation& a) { a.framesPerSecond = nan; }), "the frame rate nan fps"},
      {"InfiniteFps", ".json", with([&](Animation& a) { a.framesPerSecond = inf; }), "the frame rate inf fps"},
      {"FapZero", ".fap", with([](Animation& a) {
         a.faps = {0, 48};
       }),
       "FAP number 0 is outside 1..68"},
      {"Fap69", ".csv", with([](Animation& a) {
         a.faps = {3, 69};
       }),
       "FAP number 69 is outside 1..68"},
      {"FapsDescending", ".json", with([](Animation& a) {
         a.faps = {48, 3};
       }),
       "FAP 3 follows FAP 48: the FAP numbers must be ascending and unique"},
      {"FapsRepeated", ".fap", with([](Animation& a) {
         a.faps = {3, 3};
       }),
       "FAP 3 follows FAP 3"},
      {"ColumnsMismatch", ".csv", with([](Animation& a) { a.faps = {3}; }),
       "the values have 2 rows, but the track lists 1 FAP"},
      {"NoFrames", ".json", with([](Animation& a) { a.values.resize(2, 0); }), "the animation has no frames"},
      {"CsvOneFrame", ".csv", with([](Animation& a) { a.values.conservativeResize(2, 1); }),
       "one frame: a CSV file gives its frame rate only through time_s"},
      {"NanValue", ".csv", with([&](Animation& a) { a.values(1, 2) = nan; }),
       "frame 2, fap48 is nan: values must be finite"},
      {"InfiniteValue", ".fap", with([&](Animation& a) { a.values(0, 0) = -inf; }),
       "frame 0, fap3 is -inf: values must be finite"},
      {"FapValueBeyondInt32", ".fap", with([](Animation& a) { a.values(0, 3) = 3e9; }),
       "frame 3, fap3 is 3e+09: a .fap holds 32-bit integer values"},
      {"LastTimeOverflows", ".json", with([](Animation& a) { a.framesPerSecond = 1e-308; }),
       "the last frame's time is beyond the range of a double"},
  };
}

class InvalidAnimationWrite : public ::testing::TestWithParam<BadAnimation> {};

TEST_P(InvalidAnimationWrite, IsRefusedBeforeAnythingIsWritten) {
  const BadAnimation& bad = GetParam();
  TemporaryFolder folder;
  const fs::path path = folder.path() / ("invalid" + bad.extension);
  expectFileError(writeError(path, bad.animation), path, bad.problem);
  EXPECT_TRUE(fs::is_empty(folder.path()));
  // An existing file is left as it was.
  writeText(path, "previous");
  expectFileError(writeError(path, bad.animation), path, bad.problem);
  EXPECT_EQ(readText(path), "previous");
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{path.filename().string()});
}

INSTANTIATE_TEST_SUITE_P(Cases, InvalidAnimationWrite, ::testing::ValuesIn(badAnimations()),
                         [](const ::testing::TestParamInfo<BadAnimation>& testInfo) { return testInfo.param.label; });

TEST(AnimationFile, OneFrameIsFineOutsideCsv) {
  TemporaryFolder folder;
  const Animation one = randomAnimation(25, 1, {3}, 4);
  for (const std::string extension : {".json", ".fap"}) {
    writeAnimation(folder.path() / ("one" + extension), one);
    EXPECT_EQ(readAnimation(folder.path() / ("one" + extension)).numFrames(), 1);
  }
}

}  // namespace
}  // namespace th::formats
