// The viseme and mouth-cue formats against their documented layouts: Rhubarb Lip Sync's README ("Output
// formats") and exporters for TSV, XML, JSON and Moho's .dat; our CSV/JSON weight tables for Oculus and VRM.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/temporary_file.h"
#include "formats/animation_format.h"
#include "support/files.h"

namespace {

using th::face::FapTrack;

// Ten frames at 30 fps: rest, then "aa" from frame 3, then a closure (PP) from frame 7.
FapTrack spokenTrack(std::string source = "/clips/hi.wav") {
  FapTrack track;
  track.faps = {3};
  track.values = Eigen::MatrixXd::Zero(1, 10);
  track.source = std::move(source);
  track.visemes.classes = {0, 0, 0, 11, 11, 11, 11, 1, 1, 1};
  track.visemes.posteriors = Eigen::MatrixXd::Zero(th::face::kNumMouthClasses, 10);
  for (int t = 0; t < 10; ++t) track.visemes.posteriors(track.visemes.classes[static_cast<std::size_t>(t)], t) = 1.0;
  return track;
}

std::string written(const std::string& name, const std::string& extension, const FapTrack& track = spokenTrack()) {
  const th::TemporaryFolder folder;
  const std::filesystem::path path = folder.path() / ("out" + extension);
  th::formats::writeAnimation(path, track, th::formats::formatForWriting(path, name));
  return th::test::readText(path);
}

// Cues start half a frame before their first frame's centre, in centiseconds (frame 3: 2.5 / 30 = 0.0833 ->
// 0.08 s, frame 7: 0.2167 -> 0.22); the last
// line (TSV) or the duration is the animation's end truncated to 0.01 s (10 frames: 0.3333 -> 0.33).
TEST(RhubarbFormats, TsvHasAStartAndAShapePerLineAndEndsAtRest) {
  EXPECT_EQ(written("rhubarb-tsv", ".tsv"), "0.00\tX\n0.08\tD\n0.22\tA\n0.33\tX\n");
}

TEST(RhubarbFormats, XmlIsRhubarbsDocument) {
  EXPECT_EQ(written("rhubarb-xml", ".xml", spokenTrack("/clips/hi & bye.wav")),
            "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n"
            "<rhubarbResult>\n"
            "  <metadata>\n"
            "    <soundFile>/clips/hi &amp; bye.wav</soundFile>\n"
            "    <duration>0.33</duration>\n"
            "  </metadata>\n"
            "  <mouthCues>\n"
            "    <mouthCue start=\"0.00\" end=\"0.08\">X</mouthCue>\n"
            "    <mouthCue start=\"0.08\" end=\"0.22\">D</mouthCue>\n"
            "    <mouthCue start=\"0.22\" end=\"0.33\">A</mouthCue>\n"
            "  </mouthCues>\n"
            "</rhubarbResult>\n");
}

TEST(RhubarbFormats, JsonIsRhubarbsDocument) {
  const std::string text = written("rhubarb-json", ".json", spokenTrack("C:\\clips\\\"hi\".wav"));
  EXPECT_EQ(text,
            "{\n"
            "  \"metadata\": {\n"
            "    \"soundFile\": \"C:\\\\clips\\\\\\\"hi\\\".wav\",\n"
            "    \"duration\": 0.33\n"
            "  },\n"
            "  \"mouthCues\": [\n"
            "    { \"start\": 0.00, \"end\": 0.08, \"value\": \"X\" },\n"
            "    { \"start\": 0.08, \"end\": 0.22, \"value\": \"D\" },\n"
            "    { \"start\": 0.22, \"end\": 0.33, \"value\": \"A\" }\n"
            "  ]\n"
            "}\n");
  const nlohmann::json document = nlohmann::json::parse(text);
  EXPECT_EQ(document["metadata"]["soundFile"], "C:\\clips\\\"hi\".wav");
  EXPECT_EQ(document["mouthCues"].size(), 3u);
}

TEST(RhubarbFormats, MohoSwitchDataCountsFramesAt24PerSecondFromOne) {
  // 0.08 s is frame 1 + int(1.92) = 2; 0.22 s frame 6; the end (0.33 s) frame 8.
  EXPECT_EQ(written("moho", ".dat"), "MohoSwitch1\n1 X\n2 D\n6 A\n8 X\n");
}

TEST(RhubarbFormats, ClassesWithTheSameShapeAreOneCue) {
  FapTrack track = spokenTrack();
  track.visemes.classes = {4, 4, 4, 7, 7, 7, 14, 14, 14, 0};  // DD, SS, ih: all B
  EXPECT_EQ(written("rhubarb-tsv", ".tsv", track), "0.00\tB\n0.28\tX\n0.33\tX\n");
}

TEST(VisemeWeightFormats, OculusCsvHasTheFifteenVisemesPerFrame) {
  const std::string text = written("oculus", ".csv");
  const std::size_t firstNewline = text.find('\n');
  EXPECT_EQ(text.substr(0, firstNewline), "time_s,sil,PP,FF,TH,DD,kk,CH,SS,nn,RR,aa,E,ih,oh,ou");
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 11);
  EXPECT_NE(text.find("\n0.100000,0.0000,0.0000,0.0000,0.0000,0.0000,0.0000,0.0000,0.0000,0.0000,0.0000,1.0000,"),
            std::string::npos)
      << text;
}

TEST(VisemeWeightFormats, JsonTwinsListTheNamesAndAFramePerEntry) {
  const nlohmann::json oculus = nlohmann::json::parse(written("oculus", ".json"));
  EXPECT_EQ(oculus["fps"], 30);
  EXPECT_EQ(oculus["names"].size(), 15u);
  ASSERT_EQ(oculus["frames"].size(), 10u);
  EXPECT_DOUBLE_EQ(oculus["frames"][3]["weights"][10].get<double>(), 1.0);
  const nlohmann::json vrm = nlohmann::json::parse(written("vrm", ".json"));
  EXPECT_EQ(vrm["names"], nlohmann::json({"A", "I", "U", "E", "O"}));
  EXPECT_DOUBLE_EQ(vrm["frames"][4]["weights"][0].get<double>(), 1.0);  // aa: A
  EXPECT_DOUBLE_EQ(vrm["frames"][0]["weights"][0].get<double>(), 0.0);  // rest
  EXPECT_NEAR(vrm["frames"][4]["time"].get<double>(), 4.0 / 30.0, 1e-6);
}

TEST(AnimationFormats, TheExtensionPicksAWriterAndANameItsJsonTwin) {
  using th::formats::formatForWriting;
  EXPECT_EQ(formatForWriting("a.tsv").name(), "rhubarb-tsv");
  EXPECT_EQ(formatForWriting("a.XML").name(), "rhubarb-xml");
  EXPECT_EQ(formatForWriting("a.dat").name(), "moho");
  EXPECT_EQ(formatForWriting("a.json").name(), "json");
  EXPECT_EQ(formatForWriting("a.csv").name(), "csv");
  EXPECT_EQ(formatForWriting("a.json", "oculus").name(), "oculus-json");
  EXPECT_EQ(formatForWriting("a.csv", "vrm").name(), "vrm");
  EXPECT_EQ(formatForWriting("a.json", "rhubarb-json").name(), "rhubarb-json");
  try {
    formatForWriting("a.mp3");
    FAIL();
  } catch (const th::Error& error) {
    th::test::expectFileError(error.what(), "a.mp3", ".tsv");
  }
}

TEST(AnimationFormats, AVisemeFormatWithoutVisemesSaysSoAndLeavesNothing) {
  const th::TemporaryFolder folder;
  FapTrack track = spokenTrack();
  track.visemes = {};
  for (const char* name : {"oculus", "vrm", "rhubarb-tsv", "rhubarb-xml", "rhubarb-json", "moho"}) {
    const std::filesystem::path path = folder.path() / "out.txt";
    try {
      th::formats::writeAnimation(path, track, th::formats::animationFormat(name));
      FAIL() << name;
    } catch (const th::Error& error) {
      th::test::expectFileError(error.what(), path, "has no visemes");
    }
  }
  EXPECT_EQ(th::test::listFolder(folder.path()), std::vector<std::string>{});
}

}  // namespace
