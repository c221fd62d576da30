#include "outputs/vts_output.h"

#include <algorithm>
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <thread>
#include <utility>  // before Asio: Boost 1.74's awaitable.hpp uses std::exchange without it

#include "core/error.h"

namespace th::outputs {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using nlohmann::json;

VtsEndpoint parseVtsUrl(std::string_view url) {
  VtsEndpoint endpoint;
  if (url.empty()) return endpoint;
  constexpr std::string_view kScheme = "ws://";
  if (url.substr(0, kScheme.size()) != kScheme)
    throw Error("--vts: '" + std::string(url) +
                "' is not a ws:// URL (wss:// is not offered: VTube Studio listens on ws)");
  std::string_view rest = url.substr(kScheme.size());
  if (const std::size_t slash = rest.find('/'); slash != std::string_view::npos) {
    endpoint.path = std::string(rest.substr(slash));
    rest = rest.substr(0, slash);
  }
  if (const std::size_t colon = rest.rfind(':'); colon != std::string_view::npos) {
    endpoint.port = std::string(rest.substr(colon + 1));
    rest = rest.substr(0, colon);
    const bool digits = !endpoint.port.empty() && std::all_of(endpoint.port.begin(), endpoint.port.end(),
                                                              [](char c) { return c >= '0' && c <= '9'; });
    if (!digits || endpoint.port.size() > 5 || std::stoi(endpoint.port) < 1 || std::stoi(endpoint.port) > 65535)
      throw Error("--vts: '" + std::string(url) + "' has no port 1..65535 after the ':'");
  }
  if (rest.empty()) throw Error("--vts: '" + std::string(url) + "' has no host");
  endpoint.host = std::string(rest);
  return endpoint;
}

std::vector<std::pair<std::string, double>> vtsParameters(const AvatarFrame& frame, bool mirror) {
  const auto clamp = [](double value, double limit) { return std::clamp(value, -limit, limit); };
  const double side = mirror ? -1.0 : 1.0;
  std::vector<std::pair<std::string, double>> parameters{
      {"MouthOpen", frame.jawOpen()},
      {"MouthSmile", std::clamp(0.5 + 0.5 * (frame.smile() - frame.frown()), 0.0, 1.0)},
      {"FaceAngleX", clamp(side * frame.headDegrees[1], 30.0)},  // our yaw: to the speaker's left +
      {"FaceAngleY", clamp(-frame.headDegrees[0], 30.0)},        // our pitch looks down
      {"FaceAngleZ", clamp(side * frame.headDegrees[2], 90.0)},
  };
  for (std::size_t k = 0; k < face::kVrmVowelNames.size(); ++k)
    parameters.emplace_back("Voice" + std::string(face::kVrmVowelNames[k]), frame.vrm[k]);
  return parameters;
}

struct VtsOutput::Client {
  Client(VtsEndpoint endpointIn, std::string tokenIn, std::function<void(const std::string&)> tokenIssuedIn,
         VtsOptions optionsIn)
      : endpoint(std::move(endpointIn)),
        token(std::move(tokenIn)),
        tokenIssued(std::move(tokenIssuedIn)),
        options(std::move(optionsIn)) {}

  // The display thread's side.
  void post(const AvatarFrame& frame) {
    {
      const std::lock_guard lock(mutex);
      if (pending) ++dropped;  // replaced before the thread could send it
      pending = frame;
    }
    asio::post(io, [this] { pump(); });
  }
  OutputStatus status() const {
    const std::lock_guard lock(mutex);
    return {.name = "VTube Studio",
            .target = endpoint.text(),
            .connected = ready,
            .state = state,
            .framesSent = sent,
            .framesDropped = dropped,
            .refused = refused};
  }

  void start() {
    thread = std::thread([this] {
      connect();
      io.run();
    });
  }
  void stop() {
    io.stop();
    if (thread.joinable()) thread.join();
  }

  // The rest runs on the client's thread.
  void setState(std::string text, bool isReady) {
    const std::lock_guard lock(mutex);
    state = std::move(text);
    ready = isReady;
  }

  void connect() {
    const unsigned generation = ++connection;
    busy = false;
    missing.clear();  // a model loaded since may have them
    listed = false;
    setState("connecting", false);
    socket = std::make_unique<websocket::stream<beast::tcp_stream>>(io);
    resolver.async_resolve(
        endpoint.host, endpoint.port,
        [this, generation](beast::error_code resolving, tcp::resolver::results_type found) {
          if (generation != connection) return;
          if (resolving) return fail(generation, "cannot resolve " + endpoint.host + ": " + resolving.message());
          beast::get_lowest_layer(*socket).expires_after(std::chrono::seconds(5));
          beast::get_lowest_layer(*socket).async_connect(
              found, [this, generation](beast::error_code connecting, const tcp::endpoint&) {
                if (generation != connection) return;
                if (connecting) return fail(generation, connecting.message());
                beast::get_lowest_layer(*socket).expires_never();
                socket->set_option(websocket::stream_base::timeout::suggested(beast::role_type::client));
                socket->async_handshake(endpoint.host + ":" + endpoint.port, endpoint.path,
                                        [this, generation](beast::error_code shaking) {
                                          if (generation != connection) return;
                                          if (shaking)
                                            return fail(generation, "WebSocket handshake: " + shaking.message());
                                          authenticate(generation);
                                        });
              });
        });
  }

  void fail(unsigned generation, const std::string& why) {
    if (generation != connection) return;
    ++connection;  // handlers of this connection still queued are ignored
    const unsigned next = connection;
    char wait[32];
    std::snprintf(wait, sizeof wait, "%.0f", options.reconnectSeconds);
    setState(why + "; trying again every " + wait + " s", false);
    if (socket) beast::get_lowest_layer(*socket).close();
    retry.expires_after(std::chrono::milliseconds(static_cast<long>(options.reconnectSeconds * 1000.0)));
    retry.async_wait([this, next](beast::error_code ec) {
      if (!ec && next == connection) connect();
    });
  }

  // One request, then its answer.
  void request(unsigned generation, const std::string& type, json data, std::function<void(const json&)> answered) {
    const json message{{"apiName", "VTubeStudioPublicAPI"},
                       {"apiVersion", "1.0"},
                       {"requestID", "talkinghead-" + std::to_string(++requests)},
                       {"messageType", type},
                       {"data", std::move(data)}};
    auto text = std::make_shared<std::string>(message.dump());
    socket->text(true);
    socket->async_write(
        asio::buffer(*text), [this, generation, text, answered](beast::error_code writing, std::size_t) {
          if (generation != connection) return;
          if (writing) return fail(generation, "sending: " + writing.message());
          buffer.clear();
          socket->async_read(buffer, [this, generation, answered](beast::error_code reading, std::size_t) {
            if (generation != connection) return;
            if (reading) return fail(generation, "the connection: " + reading.message());
            const json reply = json::parse(beast::buffers_to_string(buffer.data()), nullptr, false);
            if (reply.is_discarded() || !reply.is_object() || !reply.contains("messageType"))
              return fail(generation, "VTube Studio answered something that is not its API's JSON");
            answered(reply);
          });
        });
  }

  static constexpr int kTokenRequestDenied = 50;  // Files/ErrorID.cs: TokenRequestDenied
  static constexpr int kParameterNotFound = 453;  // InjectDataParamNameNotFound

  static int errorIdOf(const json& reply) {
    const json data = reply.value("data", json::object());
    return data.is_object() && data.contains("errorID") && data["errorID"].is_number_integer()
               ? data["errorID"].get<int>()
               : -1;
  }

  static std::string errorOf(const json& reply) {
    const json data = reply.value("data", json::object());
    return data.is_object() ? data.value("message", std::string("an API error")) : std::string("an API error");
  }

  void authenticate(unsigned generation) {
    if (token.empty()) {
      setState("waiting for VTube Studio's user to allow the plugin", false);
      request(generation, "AuthenticationTokenRequest",
              {{"pluginName", options.pluginName}, {"pluginDeveloper", options.pluginDeveloper}},
              [this, generation](const json& reply) {
                const json data = reply.value("data", json::object());
                if (reply["messageType"] == "APIError" && errorIdOf(reply) == kTokenRequestDenied) {
                  // Asked again now, the question would be back in front of the user at once: wait until they
                  // ask (the output opened again).
                  {
                    const std::lock_guard lock(mutex);
                    refused = true;
                  }
                  ++connection;
                  if (socket) beast::get_lowest_layer(*socket).close();
                  return setState("VTube Studio's user denied the plugin; not asking again until asked", false);
                }
                if (reply["messageType"] != "AuthenticationTokenResponse" || !data.is_object() ||
                    !data.contains("authenticationToken") || !data["authenticationToken"].is_string())
                  return fail(generation, "no token: " + errorOf(reply));
                token = data["authenticationToken"].get<std::string>();
                if (tokenIssued) tokenIssued(token);
                authenticate(generation);
              });
      return;
    }
    setState("authenticating", false);
    request(generation, "AuthenticationRequest",
            {{"pluginName", options.pluginName},
             {"pluginDeveloper", options.pluginDeveloper},
             {"authenticationToken", token}},
            [this, generation](const json& reply) {
              const json data = reply.value("data", json::object());
              if (reply["messageType"] == "AuthenticationResponse" && data.is_object() &&
                  data.value("authenticated", false)) {
                {
                  const std::lock_guard lock(mutex);
                  ++connections;
                }
                setState("sending", true);
                return pump();
              }
              if (reply["messageType"] != "AuthenticationResponse") return fail(generation, errorOf(reply));
              token.clear();  // refused (revoked in VTube Studio): ask for a new one
              authenticate(generation);
            });
  }

  void pump() {
    std::optional<AvatarFrame> frame;
    {
      const std::lock_guard lock(mutex);
      if (!ready || busy || !pending) return;
      frame = std::move(pending);
      pending.reset();
    }
    busy = true;
    json values = json::array();
    for (const auto& [id, value] : vtsParameters(*frame, options.mirrorHead))
      if (!missing.count(id)) values.push_back({{"id", id}, {"value", value}});
    const unsigned generation = connection;
    request(generation, "InjectParameterDataRequest",
            {{"faceFound", true}, {"mode", "set"}, {"parameterValues", std::move(values)}},
            [this, generation](const json& reply) {
              {
                const std::lock_guard lock(mutex);
                if (reply["messageType"] == "InjectParameterDataResponse")
                  ++sent;
                else
                  ++dropped;
              }
              if (reply["messageType"] == "APIError" && generation == connection) {
                if (errorIdOf(reply) == kParameterNotFound && !listed) return listParameters(generation);
                setState(errorOf(reply), true);
              }
              busy = false;
              pump();
            });
  }

  // VTube Studio refused a parameter its model lacks (the whole request fails): ask it which it has, once a
  // connection, and leave out the rest.
  void listParameters(unsigned generation) {
    listed = true;
    request(generation, "InputParameterListRequest", json::object(), [this, generation](const json& reply) {
      busy = false;
      const json data = reply.value("data", json::object());
      if (reply["messageType"] != "InputParameterListResponse" || !data.is_object()) {
        setState("VTube Studio refused a parameter and did not list its own: " + errorOf(reply), true);
        return pump();
      }
      std::set<std::string> has;
      for (const char* list : {"defaultParameters", "customParameters"})
        if (data.contains(list) && data[list].is_array())
          for (const json& parameter : data[list])
            if (parameter.is_object() && parameter.contains("name") && parameter["name"].is_string())
              has.insert(parameter["name"].get<std::string>());
      std::string lacking;
      int kept = 0;
      for (const auto& [id, value] : vtsParameters(AvatarFrame{})) {
        if (has.count(id)) {
          ++kept;
          continue;
        }
        missing.insert(id);
        lacking += (lacking.empty() ? "" : ", ") + id;
      }
      if (generation == connection)
        setState("sending " + std::to_string(kept) + " parameters; VTube Studio has no " +
                     (lacking.empty() ? std::string("parameter named in its error") : lacking),
                 true);
      pump();
    });
  }

  VtsEndpoint endpoint;
  std::string token;
  std::function<void(const std::string&)> tokenIssued;
  VtsOptions options;

  asio::io_context io;
  asio::executor_work_guard<asio::io_context::executor_type> work{io.get_executor()};
  tcp::resolver resolver{io};
  asio::steady_timer retry{io};
  std::unique_ptr<websocket::stream<beast::tcp_stream>> socket;
  beast::flat_buffer buffer;
  std::thread thread;
  unsigned connection = 0;        // the current connection's number: older handlers see another and stop
  bool busy = false;              // a request is out
  std::set<std::string> missing;  // parameters VTube Studio's model lacks, left out (this connection)
  bool listed = false;            // its parameters were asked for (this connection)
  std::uint64_t requests = 0;

  mutable std::mutex mutex;  // guards what the display thread reads or leaves
  std::optional<AvatarFrame> pending;
  std::string state = "connecting";
  bool ready = false;
  bool refused = false;  // the user denied the plugin
  std::uint64_t sent = 0, dropped = 0, connections = 0;
};

VtsOutput::VtsOutput(VtsEndpoint endpoint, std::string token, std::function<void(const std::string&)> tokenIssued,
                     VtsOptions options)
    : client_(
          std::make_unique<Client>(std::move(endpoint), std::move(token), std::move(tokenIssued), std::move(options))) {
  client_->start();
}

VtsOutput::~VtsOutput() {
  client_->stop();
}

void VtsOutput::send(const AvatarFrame& frame) {
  client_->post(frame);
}

OutputStatus VtsOutput::status() const {
  return client_->status();
}

std::uint64_t VtsOutput::connections() const {
  const std::lock_guard lock(client_->mutex);
  return client_->connections;
}

}  // namespace th::outputs

namespace th::outputs {

void VtsSettings::visitOptions(OptionVisitor& v) {
  v.option(address, {.name = "",
                     .help = "Drive a VTube Studio model through its plugin API: ws://HOST:PORT",
                     .panel = false,
                     .implicitValue = kDefaultAddress});
  v.option(token, {.name = "token",
                   .help = "VTube Studio's plugin token (kept in the settings once issued; empty: ask for one)",
                   .panel = false});
}

void VtsSettings::addRows(std::vector<OutputRow>& rows) {
  rows.push_back({"VTube Studio", "VTube Studio", &address, kDefaultAddress});
}

void VtsSettings::open(const OutputContext& context, std::vector<std::unique_ptr<LiveOutput>>& outputs) const {
  if (address.empty()) return;
  outputs.push_back(std::make_unique<VtsOutput>(parseVtsUrl(address), token, context.tokenIssued,
                                                VtsOptions{.mirrorHead = context.mirrorHead}));
}

}  // namespace th::outputs
