// `talkinghead live --headless` sending to real receivers: liblo's oscdump for VMC and plain OSC, and a WebSocket
// server speaking VTube Studio's plugin API (vts_server.py, python3-websockets): every frame arrives in the
// protocol's shape and types, at the animation's rate, and its values follow the speech; VTube Studio's token is
// asked for, kept and used again, and a server that restarts is reconnected to.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "audio/audio_file.h"
#include "cli_runner.h"
#include "core/data_path.h"

namespace {

namespace fs = std::filesystem;
using th::test::CliResult;
using th::test::runCli;

int shell(const std::string& command) {
  return std::system(command.c_str());  // NOLINT(concurrency-mt-unsafe): the tests run one command at a time
}

// A port nothing listens on now (bound, read and released; the receiver takes it at once).
int freePort(int type) {
  const int fd = ::socket(AF_INET, type, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address);
  socklen_t length = sizeof address;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  ::close(fd);
  return ntohs(address.sin_port);
}

fs::path prompt() {
  return th::sharedDataPath("speech/arctic/arctic_a0001.wav");
}

// The recording's level (dB) in each 1/30 s frame, centred at i / 30 s as the features are.
std::vector<double> frameLevelsDb(int frames) {
  const th::audio::AudioClip clip = th::audio::readAudioFile(prompt());
  const double hop = clip.sampleRateHz / 30.0;
  std::vector<double> levels;
  for (int i = 0; i < frames; ++i) {
    double sum = 1e-12;
    int count = 0;
    for (auto n = static_cast<long>(std::max(0.0, i * hop - hop / 2));
         n < static_cast<long>(i * hop + hop / 2) && n < static_cast<long>(clip.samples.size()); ++n, ++count)
      sum += clip.samples[static_cast<std::size_t>(n)] * clip.samples[static_cast<std::size_t>(n)];
    levels.push_back(10.0 * std::log10(sum / std::max(count, 1)));
  }
  return levels;
}

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const std::size_t n = std::min(a.size(), b.size());
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < n; ++i) {
    ma += a[i] / static_cast<double>(n);
    mb += b[i] / static_cast<double>(n);
  }
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

// One message as oscdump prints it: "TIMETAG PATH TYPES ARG...".
struct OscLine {
  std::string path, types;
  std::vector<std::string> arguments;
};

std::vector<OscLine> readOscdump(const fs::path& file) {
  std::vector<OscLine> lines;
  std::ifstream in(file);
  std::string text;
  while (std::getline(in, text)) {
    std::istringstream fields(text);
    std::string timetag;
    OscLine line;
    fields >> timetag >> line.path;
    if (line.path.empty() || line.path[0] != '/') continue;
    std::string argument;
    if (!(fields >> line.types)) line.types.clear();
    while (fields >> argument) line.arguments.push_back(argument);
    if (!line.types.empty() && line.types.find_first_not_of("sfiTF") != std::string::npos) {
      line.arguments.insert(line.arguments.begin(), line.types);  // no type tags: oscdump prints none
      line.types.clear();
    }
    lines.push_back(line);
  }
  return lines;
}

class LiveOutputsTest : public th::test::CliTest {
 protected:
  // oscdump on a free port, its messages into `file`; returns the port.
  int startOscdump(const fs::path& file, const std::string& name) {
    const int port = freePort(SOCK_DGRAM);
    const fs::path pid = out() / (name + ".pid");
    shell("oscdump -L " + std::to_string(port) + " > " + file.string() + " 2>&1 & echo $! > " + pid.string());
    pids_.push_back(pid);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // listening
    return port;
  }
  void TearDown() override {
    for (const fs::path& pid : pids_) shell("kill $(cat " + pid.string() + ") > /dev/null 2>&1");
  }
  std::vector<fs::path> pids_;
};

TEST_F(LiveOutputsTest, VmcAndOscReceiversGetEveryFrameInTheProtocolsShapeAndItFollowsTheSpeech) {
  const fs::path vmcFile = out() / "vmc.txt", oscFile = out() / "osc.txt";
  const int vmcPort = startOscdump(vmcFile, "vmc");
  const int oscPort = startOscdump(oscFile, "osc");
  const fs::path assistantFile = out() / "assistant.txt";
  const int assistantPort = startOscdump(assistantFile, "assistant");
  const fs::path vrchatFile = out() / "vrchat.txt";
  const int vrchatPort = startOscdump(vrchatFile, "vrchat");
  const CliResult result =
      runCli({"live", "--headless", "--input", prompt().string(), "--no-settings", "--vmc",
              "127.0.0.1:" + std::to_string(vmcPort), "--osc", std::to_string(oscPort), "--vmc-assistant",
              std::to_string(assistantPort), "--vrchat", std::to_string(vrchatPort), "--blinks-per-minute", "40"},
             logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the last datagrams printed
  std::printf("%s", result.out.c_str());
  int shown = 0;
  ASSERT_EQ(
      std::sscanf(result.out.substr(result.out.find("frames: ")).c_str(), "frames: %*d decoded, %d shown", &shown), 1);
  EXPECT_GT(shown, 95);  // 3.35 s at 30 frames a second

  // VMC: per frame OK, T, Root/Pos, Bone/Pos Neck and Head, VRM's 7 Blend/Val, Apply; types as the protocol's.
  const std::vector<OscLine> vmc = readOscdump(vmcFile);
  std::map<std::string, int> count;
  std::vector<double> times, vowels;
  double mostClosed = 0.0;
  for (const OscLine& line : vmc) {
    ++count[line.path];
    if (line.path == "/VMC/Ext/OK") {
      EXPECT_EQ(line.types, "i");
    }
    if (line.path == "/VMC/Ext/T") {
      EXPECT_EQ(line.types, "f");
      times.push_back(std::stod(line.arguments.at(0)));
    }
    if (line.path == "/VMC/Ext/Blend/Val") {
      ASSERT_EQ(line.types, "sf");
      ++count["name " + line.arguments.at(0)];
      const double value = std::stod(line.arguments.at(1));
      EXPECT_GE(value, 0.0);
      EXPECT_LE(value, 1.0);
      if (line.arguments[0] == "\"A\"") vowels.push_back(value);
      if (line.arguments[0] == "\"Blink_L\"") mostClosed = std::max(mostClosed, value);
      if (line.arguments[0] == "\"I\"" || line.arguments[0] == "\"U\"" || line.arguments[0] == "\"E\"" ||
          line.arguments[0] == "\"O\"")
        vowels.back() += value;
    }
    if (line.path == "/VMC/Ext/Bone/Pos" || line.path == "/VMC/Ext/Root/Pos") {
      ASSERT_EQ(line.types, "sfffffff");
      ++count["bone " + line.arguments.at(0)];
      double norm = 0.0;
      for (int k = 4; k < 8; ++k) norm += std::pow(std::stod(line.arguments.at(static_cast<std::size_t>(k))), 2);
      EXPECT_NEAR(norm, 1.0, 1e-4) << "a unit quaternion";
    }
  }
  EXPECT_EQ(count["/VMC/Ext/Blend/Apply"], shown) << "every frame, none lost on the loopback";
  EXPECT_EQ(count["/VMC/Ext/Bone/Pos"], 2 * shown);
  EXPECT_EQ(count["bone \"Neck\""], shown);
  EXPECT_EQ(count["bone \"Head\""], shown);
  EXPECT_EQ(count["bone \"root\""], shown);
  EXPECT_EQ(count["/VMC/Ext/OK"], shown);
  EXPECT_EQ(count["/VMC/Ext/Blend/Val"], 7 * shown) << "VRM's names alone: the mouth driven once";
  for (const char* name : {"\"A\"", "\"I\"", "\"U\"", "\"E\"", "\"O\"", "\"Blink_L\"", "\"Blink_R\""})
    EXPECT_EQ(count[std::string("name ") + name], shown) << name;
  EXPECT_GT(mostClosed, 0.5) << "headless blinks as the window does (40 a minute here)";
  // The frames' times: 30 a second, in order.
  ASSERT_EQ(static_cast<int>(times.size()), shown);
  for (std::size_t i = 1; i < times.size(); ++i) EXPECT_NEAR(times[i] - times[i - 1], 1.0 / 30.0, 1e-4);
  // The rate it went out at: the recording's pace.
  const std::size_t rateAt = result.out.find("output VMC");
  ASSERT_NE(rateAt, std::string::npos);
  double rate = 0.0;
  ASSERT_EQ(std::sscanf(result.out.c_str() + result.out.find("sent, ", rateAt), "sent, %lf a second", &rate), 1);
  EXPECT_NEAR(rate, 30.0, 3.0);
  // The vowels are heard in speech, not in the silences around it.
  const std::vector<double> levels = frameLevelsDb(shown);
  // The louder half of the frames against the quietest fifth (the prompt's pauses and its ends).
  std::vector<double> sorted = levels;
  std::sort(sorted.begin(), sorted.end());
  const double loud = sorted[sorted.size() / 2], quiet = sorted[sorted.size() / 5];
  double speech = 0, silence = 0;
  int speechFrames = 0, silenceFrames = 0;
  for (std::size_t i = 0; i < vowels.size() && i < levels.size(); ++i) {
    if (levels[i] >= loud) speech += vowels[i], ++speechFrames;
    if (levels[i] <= quiet) silence += vowels[i], ++silenceFrames;
  }
  std::printf("[ INFO     ] VMC's vowels A+I+U+E+O: %.3f in the louder half, %.3f in the quietest fifth\n",
              speech / speechFrames, silence / silenceFrames);
  EXPECT_GT(speech / speechFrames, silence / silenceFrames + 0.15);

  // The assistant: the blendshapes alone, every frame.
  std::map<std::string, int> assistant;
  for (const OscLine& line : readOscdump(assistantFile)) ++assistant[line.path];
  EXPECT_EQ(assistant["/VMC/Ext/Blend/Apply"], shown);
  EXPECT_EQ(assistant["/VMC/Ext/Blend/Val"], 7 * shown);
  EXPECT_EQ(assistant.size(), 2U) << "no bones, no time, no root to a Performer";

  // VRChat: avatar parameters alone, one value a message, the face's changes.
  std::map<std::string, int> vrchat;
  for (const OscLine& line : readOscdump(vrchatFile)) {
    ++vrchat[line.path];
    EXPECT_EQ(line.path.rfind("/avatar/parameters/", 0), 0U) << line.path;
    EXPECT_TRUE(line.types == "f" || line.types == "T") << line.path << " " << line.types;
  }
  EXPECT_GE(vrchat["/avatar/parameters/LipTrackingActive"], 1);
  EXPECT_GT(vrchat["/avatar/parameters/FT/v2/JawOpen"], shown / 3) << "the jaw moves with the speech";
  EXPECT_LE(vrchat["/avatar/parameters/FT/v2/JawOpen"], shown);
  EXPECT_GE(vrchat["/avatar/parameters/FT/v2/EyeLidLeft"], 2) << "the blinks";

  // Plain OSC: a bundle per frame with the FAPs, the visemes, VRM's vowels and the head; the jaw opens with the
  // voice.
  std::map<std::string, int> osc;
  std::vector<double> jaw;
  for (const OscLine& line : readOscdump(oscFile)) {
    ++osc[line.path];
    if (line.path == "/talkinghead/jaw") jaw.push_back(std::stod(line.arguments.at(0)));
    if (line.path == "/talkinghead/head") {
      EXPECT_EQ(line.types, "fff");
    }
    if (line.path.rfind("/talkinghead/fap/", 0) == 0 || line.path.rfind("/talkinghead/viseme/", 0) == 0) {
      EXPECT_EQ(line.types, "f");
    }
  }
  for (const char* path :
       {"/talkinghead/time", "/talkinghead/fap/3", "/talkinghead/fap/48", "/talkinghead/head", "/talkinghead/jaw"})
    EXPECT_EQ(osc[path], shown) << path;
  // The visemes from the first frame the viseme model has decided (its context and lag: a few frames in).
  for (const char* path : {"/talkinghead/viseme/sil", "/talkinghead/viseme/aa", "/talkinghead/vrm/A"}) {
    EXPECT_LE(osc[path], shown) << path;
    EXPECT_GE(osc[path], shown - 6) << path;
  }
  const double r = correlation(jaw, levels);
  std::printf("[ INFO     ] OSC jaw against the recording's level: r = %.3f\n", r);
  EXPECT_GT(r, 0.5);
}

TEST_F(LiveOutputsTest, AReceiverThatIsNotThereCostsNothingButDroppedFrames) {
  const int port = freePort(SOCK_DGRAM);  // nobody listens: the kernel refuses, the face goes on
  const CliResult result = runCli(
      {"live", "--headless", "--input", prompt().string(), "--no-settings", "--vmc", std::to_string(port)}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("0 dropped; samples"), std::string::npos) << "no animation frame lost:\n" << result.out;
  EXPECT_NE(result.out.find("output VMC 127.0.0.1:" + std::to_string(port)), std::string::npos) << result.out;
}

TEST_F(LiveOutputsTest, BadAddressesFailInOneLine) {
  th::test::expectOneLineFailure(
      runCli({"live", "--headless", "--input", prompt().string(), "--no-settings", "--vmc", "host:port"}, logs()),
      "--vmc", "not [HOST:]PORT");
  th::test::expectOneLineFailure(
      runCli({"live", "--headless", "--input", prompt().string(), "--no-settings", "--osc", "70000"}, logs()), "--osc",
      "port 1..65535");
  th::test::expectOneLineFailure(
      runCli({"live", "--headless", "--input", prompt().string(), "--no-settings", "--vts", "http://localhost:8001"},
             logs()),
      "--vts", "not a ws:// URL");
}

// VTube Studio's side, played by vts_server.py.
class VtsServer {
 public:
  // `extra`: more of vts_server.py's options ("--deny", "--parameters A,B").
  VtsServer(const fs::path& folder, int port = 0, const std::string& extra = "") : folder_(folder) {
    const fs::path portFile = folder_ / "port";
    fs::remove(portFile);
    shell("/usr/bin/python3 " + std::string(TALKINGHEAD_TESTS_DIR) + "/cli/vts_server.py --port-file " +
          portFile.string() + " --port " + std::to_string(port) + " --log " + log().string() + " " + extra + " > " +
          (folder_ / "server.txt").string() + " 2>&1 & echo $! > " + (folder_ / "server.pid").string());
    for (int i = 0; i < 200 && port_ == 0; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      std::ifstream(portFile) >> port_;
    }
  }
  ~VtsServer() { stop(); }
  void stop() { shell("kill $(cat " + (folder_ / "server.pid").string() + ") > /dev/null 2>&1"); }
  int port() const { return port_; }
  std::string url() const { return "ws://127.0.0.1:" + std::to_string(port_); }
  fs::path log() const { return folder_ / "requests.jsonl"; }
  std::vector<nlohmann::json> requests() const {
    std::vector<nlohmann::json> all;
    std::ifstream in(log());
    std::string line;
    while (std::getline(in, line)) all.push_back(nlohmann::json::parse(line));
    return all;
  }

 private:
  fs::path folder_;
  int port_ = 0;
};

int countOf(const std::vector<nlohmann::json>& requests, const std::string& type, std::size_t from = 0) {
  int n = 0;
  for (std::size_t i = from; i < requests.size(); ++i) n += requests[i]["type"] == type ? 1 : 0;
  return n;
}

TEST_F(LiveOutputsTest, VtubeStudioIsAskedForATokenOnceAndDrivenEachFrameInTheApisShape) {
  VtsServer server(out());
  ASSERT_GT(server.port(), 0) << th::test::readText(out() / "server.txt");
  const fs::path settings = out() / "live.json";
  const CliResult first = runCli(
      {"live", "--headless", "--input", prompt().string(), "--settings", settings.string(), "--vts", server.url()},
      logs());
  ASSERT_EQ(first.exitCode, 0) << first.err;
  std::printf("%s", first.out.c_str());
  const std::vector<nlohmann::json> requests = server.requests();
  ASSERT_GE(requests.size(), 3U);
  EXPECT_EQ(requests[0]["type"], "AuthenticationTokenRequest");
  EXPECT_EQ(requests[1]["type"], "AuthenticationRequest");
  EXPECT_EQ(requests[1]["request"]["data"]["authenticationToken"], "talkinghead-test-token");
  for (const nlohmann::json& request : requests) EXPECT_TRUE(request["problems"].empty()) << request.dump();
  const int injected = countOf(requests, "InjectParameterDataRequest");
  EXPECT_GT(injected, 90);
  const nlohmann::json& inject = requests.back()["request"]["data"];
  EXPECT_EQ(inject["mode"], "set");
  std::vector<std::string> ids;
  for (const nlohmann::json& value : inject["parameterValues"]) ids.push_back(value["id"]);
  EXPECT_EQ(ids, (std::vector<std::string>{"MouthOpen", "MouthSmile", "FaceAngleX", "FaceAngleY", "FaceAngleZ",
                                           "VoiceA", "VoiceI", "VoiceU", "VoiceE", "VoiceO"}));
  // MouthOpen follows the voice.
  std::vector<double> mouth;
  for (const nlohmann::json& request : requests)
    if (request["type"] == "InjectParameterDataRequest")
      mouth.push_back(request["request"]["data"]["parameterValues"][0]["value"].get<double>());
  const double r = correlation(mouth, frameLevelsDb(static_cast<int>(mouth.size())));
  std::printf("[ INFO     ] VTube Studio MouthOpen against the recording's level: r = %.3f\n", r);
  EXPECT_GT(r, 0.4);
  // The token is kept, and the next run authenticates with it without asking again.
  EXPECT_EQ(nlohmann::json::parse(th::test::readText(settings))["vts_token"], "talkinghead-test-token");
  const CliResult second = runCli(
      {"live", "--headless", "--input", prompt().string(), "--settings", settings.string(), "--vts", server.url()},
      logs());
  ASSERT_EQ(second.exitCode, 0) << second.err;
  const std::vector<nlohmann::json> again = server.requests();
  EXPECT_EQ(countOf(again, "AuthenticationTokenRequest", requests.size()), 0);
  EXPECT_EQ(again.at(requests.size())["type"], "AuthenticationRequest");
  EXPECT_GT(countOf(again, "InjectParameterDataRequest", requests.size()), 90);
}

TEST_F(LiveOutputsTest, VtubeStudioRestartingIsConnectedToAgain) {
  auto server = std::make_unique<VtsServer>(out());
  ASSERT_GT(server->port(), 0);
  const int port = server->port();
  const std::string url = server->url();
  CliResult result;
  std::thread run([&] {
    result =
        runCli({"live", "--headless", "--input", prompt().string(), "--repeat-to", "9", "--no-settings", "--vts", url},
               logs());
  });
  const auto injected = [&] { return countOf(server->requests(), "InjectParameterDataRequest"); };
  for (int i = 0; i < 100 && injected() < 30; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const std::size_t before = server->requests().size();
  server.reset();  // VTube Studio quits...
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  server = std::make_unique<VtsServer>(out(), port);  // ...and comes back on its port
  run.join();
  ASSERT_EQ(result.exitCode, 0) << result.err;
  std::printf("%s", result.out.c_str());
  const std::vector<nlohmann::json> requests = server->requests();
  ASSERT_GT(before, 30U);
  EXPECT_GE(countOf(requests, "AuthenticationRequest", before), 1) << "authenticated again";
  EXPECT_GT(countOf(requests, "InjectParameterDataRequest", before), 30) << "and driven again";
  EXPECT_EQ(result.out.find(" 0 dropped; sending"), std::string::npos) << "frames were dropped while it was gone";
}

}  // namespace

TEST_F(LiveOutputsTest, VtubeStudiosDenialIsAskedNoMoreUntilTheUserAsks) {
  VtsServer server(out(), 0, "--deny");
  ASSERT_GT(server.port(), 0) << th::test::readText(out() / "server.txt");
  const CliResult result = runCli(
      {"live", "--headless", "--input", prompt().string(), "--repeat-to", "8", "--no-settings", "--vts", server.url()},
      logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  // Over 8 s (four of the old 2 s retries), one question put to the user, and the run's summary says why.
  const std::vector<nlohmann::json> requests = server.requests();
  EXPECT_EQ(countOf(requests, "AuthenticationTokenRequest"), 1);
  EXPECT_EQ(countOf(requests, "InjectParameterDataRequest"), 0);
  EXPECT_NE(result.out.find("denied the plugin"), std::string::npos) << result.out;
}

TEST_F(LiveOutputsTest, AVtubeStudioModelWithoutTheVoiceParametersGetsTheOthers) {
  VtsServer server(out(), 0, "--parameters MouthOpen,MouthSmile,FaceAngleX,FaceAngleY,FaceAngleZ");
  ASSERT_GT(server.port(), 0) << th::test::readText(out() / "server.txt");
  const CliResult result =
      runCli({"live", "--headless", "--input", prompt().string(), "--no-settings", "--vts", server.url()}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const std::vector<nlohmann::json> requests = server.requests();
  // One request refused (453), the parameters asked for once, and from then on every frame taken.
  EXPECT_EQ(countOf(requests, "InputParameterListRequest"), 1);
  int refused = 0, taken = 0;
  for (const nlohmann::json& request : requests) {
    if (request["type"] != "InjectParameterDataRequest") continue;
    if (request["problems"].empty()) {
      ++taken;
      EXPECT_EQ(request["request"]["data"]["parameterValues"].size(), 5U);
    } else {
      ++refused;
    }
  }
  EXPECT_EQ(refused, 1);
  EXPECT_GT(taken, 90);
  EXPECT_NE(result.out.find("VTube Studio has no VoiceA, VoiceI, VoiceU, VoiceE, VoiceO"), std::string::npos)
      << result.out;
}
