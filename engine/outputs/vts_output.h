// The VTube Studio plugin API (https://github.com/DenchiSoft/VTubeStudio, WebSocket, JSON): the face drives a
// VTube Studio model's default input parameters. On its own thread (Boost.Beast):
//   1. connect to ws://HOST:PORT (VTube Studio's API server, default ws://localhost:8001);
//   2. without a token: AuthenticationTokenRequest (VTube Studio asks its user to allow the plugin) and the
//      token issued handed to tokenIssued, for the settings to keep; if the user denies it (APIError 50), the
//      output stops there and says so (status().refused) until it is opened again (the panel's button, or the
//      next run): asking again unbidden would put the question back in front of the user every few seconds;
//   3. AuthenticationRequest with the token (a token refused is forgotten and a new one asked for);
//   4. each frame, InjectParameterDataRequest ("set", faceFound) of the default parameters in their documented
//      ranges (vtsParameters); if VTube Studio refuses one it does not have (APIError 453: the whole request
//      fails), it is asked once a connection for its parameters (InputParameterListRequest), and those it lacks
//      are left out from then on, as status() says;
//   5. a lost connection is tried again every reconnectSeconds, from step 1.
// send() never waits: it leaves the newest frame for the thread, and a frame it replaces unsent is dropped,
// counted. Each request is answered before the next is sent.
// Thread contract: as LiveOutput; tokenIssued is called on the output's own thread.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "outputs/live_output.h"

namespace th::outputs {

struct VtsEndpoint {
  std::string host = "localhost";
  std::string port = "8001";
  std::string path = "/";
  std::string text() const { return "ws://" + host + ":" + port + path; }
};
// "ws://HOST[:PORT][/PATH]" (or "" for the default); throws th::Error naming --vts and what is wrong.
VtsEndpoint parseVtsUrl(std::string_view url);

struct VtsOptions {
  std::string pluginName = "talkinghead";
  std::string pluginDeveloper = "talkinghead";
  double reconnectSeconds = 2.0;
  bool mirrorHead = false;  // the avatar turns as the speaker's mirror image (as VMC's --mirror-head)
};

// `live --vts ws://HOST:PORT` and the token VTube Studio issued (live_output.h: an output's settings).
struct VtsSettings {
  static constexpr std::string_view kPrefix = "vts";
  static constexpr std::string_view kDefaultAddress = "ws://localhost:8001";
  std::string address;  // the plugin API's URL (empty: off)
  std::string token;    // VTube Studio's authentication token, kept from the run that was issued it

  void visitOptions(OptionVisitor& v);
  void addRows(std::vector<OutputRow>& rows);
  void open(const OutputContext& context, std::vector<std::unique_ptr<LiveOutput>>& outputs) const;
};

class VtsOutput final : public LiveOutput {
 public:
  VtsOutput(VtsEndpoint endpoint, std::string token, std::function<void(const std::string&)> tokenIssued,
            VtsOptions options = {});
  ~VtsOutput() override;
  VtsOutput(const VtsOutput&) = delete;
  VtsOutput& operator=(const VtsOutput&) = delete;

  void send(const AvatarFrame& frame) override;
  OutputStatus status() const override;
  std::uint64_t connections() const;  // sessions authenticated so far (a reconnection adds one)

 private:
  struct Client;
  std::unique_ptr<Client> client_;
};

// The InjectParameterDataRequest of one frame (its "data" object's parameterValues as name, value pairs), for
// tests and for anyone mapping the face onto VTube Studio by hand:
// - MouthOpen 0..1 (jawOpen); MouthSmile 0..1 with 0.5 at rest (VTube Studio's default mapping turns 0..1 into
//   the mouth form's -1..1: 0.5 + (smile - frown) / 2);
// - FaceAngleX, FaceAngleY -30..30 and FaceAngleZ -90..90 degrees: the avatar turns as the speaker does (to its
//   own left when the speaker turns to theirs, as VMC's head): Live2D's angle X is positive toward the screen's
//   right, which is the character's own left, so FaceAngleX is our yaw; FaceAngleY up +; FaceAngleZ our roll;
//   `mirror` turns yaw and roll the other way (the avatar as the speaker's mirror image);
// - VoiceA, VoiceI, VoiceU, VoiceE, VoiceO 0..1 (the VRM vowels; no custom parameters, so none to register).
std::vector<std::pair<std::string, double>> vtsParameters(const AvatarFrame& frame, bool mirror = false);

}  // namespace th::outputs
