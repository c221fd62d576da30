#include "outputs/osc_sender.h"

#include <fcntl.h>
#include <lo/lo.h>
#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>

#include "core/error.h"
#include "outputs/live_output.h"

namespace th::outputs {

UdpEndpoint parseUdpEndpoint(std::string_view text, int defaultPort, std::string_view option) {
  UdpEndpoint endpoint;
  endpoint.port = defaultPort;
  if (text.empty()) return endpoint;
  std::string_view portText = text;
  if (const std::size_t colon = text.rfind(':'); colon != std::string_view::npos) {
    endpoint.host = std::string(text.substr(0, colon));
    portText = text.substr(colon + 1);
    if (endpoint.host.empty())
      throw Error(std::string(option) + ": '" + std::string(text) + "' has no host before the ':'");
  }
  int port = 0;
  const auto [end, error] = std::from_chars(portText.data(), portText.data() + portText.size(), port);
  if (error != std::errc() || end != portText.data() + portText.size() || port < 1 || port > 65535)
    throw Error(std::string(option) + ": '" + std::string(text) + "' is not [HOST:]PORT with a port 1..65535");
  endpoint.port = port;
  return endpoint;
}

namespace {
lo_bundle immediateBundle() {
  lo_timetag immediately{0U, 1U};  // LO_TT_IMMEDIATE, which is a C compound literal
  return lo_bundle_new(immediately);
}
}  // namespace

OscBundle::OscBundle() : bundle_(immediateBundle()) {}

OscBundle::~OscBundle() {
  lo_bundle_free_recursive(static_cast<lo_bundle>(bundle_));
}

OscBundle::Message OscBundle::add(std::string_view path) {
  lo_message message = lo_message_new();
  paths_.emplace_back(path);
  lo_bundle_add_message(static_cast<lo_bundle>(bundle_), paths_.back().c_str(), message);
  return Message(message);
}

OscBundle::Message& OscBundle::Message::string(std::string_view value) {
  lo_message_add_string(static_cast<lo_message>(message_), std::string(value).c_str());
  return *this;
}
OscBundle::Message& OscBundle::Message::real(float value) {
  lo_message_add_float(static_cast<lo_message>(message_), value);
  return *this;
}
OscBundle::Message& OscBundle::Message::integer(std::int32_t value) {
  lo_message_add_int32(static_cast<lo_message>(message_), value);
  return *this;
}
OscBundle::Message& OscBundle::Message::boolean(bool value) {
  if (value)
    lo_message_add_true(static_cast<lo_message>(message_));
  else
    lo_message_add_false(static_cast<lo_message>(message_));
  return *this;
}

namespace {
std::size_t padded(std::size_t bytes) {
  return (bytes + 3) / 4 * 4;
}
constexpr std::size_t kBundleHeaderBytes = 16;  // "#bundle\0" and the time tag
}  // namespace

std::size_t OscMessage::bytes() const {
  std::size_t size = padded(path.size() + 1) + padded(arguments.size() + 2);  // path, ",TYPES"
  for (const auto& argument : arguments) {
    if (const auto* text = std::get_if<std::string>(&argument))
      size += padded(text->size() + 1);
    else if (!std::holds_alternative<bool>(argument))
      size += 4;
  }
  return size + 4;  // the bundle element's size prefix
}

std::vector<std::vector<OscMessage>> cutIntoDatagrams(std::vector<OscMessage> messages, int maxBytes) {
  std::vector<std::vector<OscMessage>> datagrams(1);
  std::size_t size = kBundleHeaderBytes;
  for (OscMessage& message : messages) {
    const std::size_t bytes = message.bytes();
    if (!datagrams.back().empty() && size + bytes > static_cast<std::size_t>(maxBytes)) {
      datagrams.emplace_back();
      size = kBundleHeaderBytes;
    }
    size += bytes;
    datagrams.back().push_back(std::move(message));
  }
  return datagrams;
}

std::vector<char> serialiseBundle(const std::vector<OscMessage>& messages) {
  OscBundle bundle;
  for (const OscMessage& message : messages) {
    OscBundle::Message added = bundle.add(message.path);
    for (const auto& argument : message.arguments) {
      if (const auto* text = std::get_if<std::string>(&argument)) added.string(*text);
      if (const auto* number = std::get_if<float>(&argument)) added.real(*number);
      if (const auto* integer = std::get_if<std::int32_t>(&argument)) added.integer(*integer);
      if (const auto* flag = std::get_if<bool>(&argument)) added.boolean(*flag);
    }
  }
  return bundle.serialise();
}

std::vector<char> OscBundle::serialise() const {
  const auto bundle = static_cast<lo_bundle>(bundle_);
  std::size_t size = lo_bundle_length(bundle);
  std::vector<char> bytes(size);
  lo_bundle_serialise(bundle, bytes.data(), &size);
  bytes.resize(size);
  return bytes;
}

OscSender::OscSender(UdpEndpoint endpoint) : endpoint_(std::move(endpoint)) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  const std::string port = std::to_string(endpoint_.port);
  if (const int status = getaddrinfo(endpoint_.host.c_str(), port.c_str(), &hints, &found); status != 0)
    throw Error("OSC: cannot resolve '" + endpoint_.host + "': " + gai_strerror(status));
  socket_ = ::socket(found->ai_family, SOCK_DGRAM, 0);
  if (socket_ < 0) {
    freeaddrinfo(found);
    throw Error("OSC: cannot open a UDP socket: " + std::string(std::strerror(errno)));
  }
  fcntl(socket_, F_SETFL, fcntl(socket_, F_GETFL) | O_NONBLOCK);
  address_.assign(reinterpret_cast<const unsigned char*>(found->ai_addr),
                  reinterpret_cast<const unsigned char*>(found->ai_addr) + found->ai_addrlen);
  addressLength_ = static_cast<unsigned>(found->ai_addrlen);
  freeaddrinfo(found);
}

OscSender::~OscSender() {
  if (socket_ >= 0) ::close(socket_);
}

bool OscSender::send(const OscBundle& bundle) {
  return send(bundle.serialise());
}

bool OscSender::send(const std::vector<char>& bytes) {
  const ssize_t written = ::sendto(socket_, bytes.data(), bytes.size(), MSG_DONTWAIT,
                                   reinterpret_cast<const sockaddr*>(address_.data()), addressLength_);
  lastSent_ = written == static_cast<ssize_t>(bytes.size());
  if (!lastSent_) {
    ++dropped_;  // EAGAIN (the socket's buffer is full) or ECONNREFUSED (nobody listened to the last one)
    return false;
  }
  ++sent_;
  bytes_ += bytes.size();
  return true;
}

OutputStatus OscSender::statusAs(std::string name) const {
  return {.name = std::move(name),
          .target = endpoint_.text(),
          .connected = lastSent_,
          .state = lastSent_ ? "sending" : (sent_ + dropped_ == 0 ? "waiting" : "not taken"),
          .framesSent = sent_,
          .framesDropped = dropped_};
}

}  // namespace th::outputs
