// OSC over UDP, sent without ever blocking: liblo builds and serialises each bundle (OSC 1.0, as VMC and
// VRChat read it), and a non-blocking socket of our own sends it, so that a receiver that is gone, slow or
// absent costs the caller nothing but a dropped bundle, counted.
//
//   th::outputs::OscSender sender(th::outputs::parseUdpEndpoint("127.0.0.1:39539", 39539, "--vmc"));
//   th::outputs::OscBundle bundle;
//   bundle.add("/VMC/Ext/Blend/Val").string("A").real(0.5f);
//   bundle.add("/VMC/Ext/Blend/Apply");
//   sender.send(bundle);                 // false (and counted) if the network would not take it now
//
// Thread contract: an OscSender and an OscBundle belong to one thread at a time.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace th::outputs {

struct OutputStatus;

struct UdpEndpoint {
  std::string host = "127.0.0.1";
  int port = 0;
  std::string text() const { return host + ":" + std::to_string(port); }
};

// "[HOST:]PORT", or "" for defaultPort on 127.0.0.1. Throws th::Error naming `option` and what is wrong.
UdpEndpoint parseUdpEndpoint(std::string_view text, int defaultPort, std::string_view option);

// One OSC bundle of messages (liblo's lo_bundle), built message by message.
class OscBundle {
 public:
  OscBundle();
  ~OscBundle();
  OscBundle(const OscBundle&) = delete;
  OscBundle& operator=(const OscBundle&) = delete;

  class Message {
   public:
    Message& string(std::string_view value);
    Message& real(float value);
    Message& integer(std::int32_t value);
    Message& boolean(bool value);  // OSC's T or F: a type tag, no bytes

   private:
    friend class OscBundle;
    explicit Message(void* message) : message_(message) {}
    void* message_;  // lo_message, owned by the bundle
  };
  Message add(std::string_view path);
  int messages() const { return static_cast<int>(paths_.size()); }
  // The bundle's bytes as sent (liblo's serialisation).
  std::vector<char> serialise() const;

 private:
  void* bundle_;                   // lo_bundle
  std::deque<std::string> paths_;  // the paths stay where they are while the bundle lives (liblo may point to them)
};

// One OSC message as a value: int32, float32, string and boolean (T/F) arguments only, what the receivers' OSC
// libraries read (uOSC, VRChat's).
struct OscMessage {
  std::string path;
  std::vector<std::variant<std::int32_t, float, std::string, bool>> arguments;
  std::size_t bytes() const;  // its size in a bundle, the size prefix included (OSC 1.0)
};

// Messages cut, in order, into bundles of at most maxBytes each (one datagram each: unfragmented under the
// usual 1,500-byte MTU at 1,400), and serialised.
std::vector<std::vector<OscMessage>> cutIntoDatagrams(std::vector<OscMessage> messages, int maxBytes);
std::vector<char> serialiseBundle(const std::vector<OscMessage>& messages);

class OscSender {
 public:
  // Resolves the host (throws th::Error naming it if it cannot) and opens a non-blocking UDP socket.
  explicit OscSender(UdpEndpoint endpoint);
  ~OscSender();
  OscSender(const OscSender&) = delete;
  OscSender& operator=(const OscSender&) = delete;

  bool send(const OscBundle& bundle);            // false: dropped (the socket would block, or the receiver refused it)
  bool send(const std::vector<char>& datagram);  // bytes already serialised
  const UdpEndpoint& endpoint() const { return endpoint_; }
  std::uint64_t sent() const { return sent_; }
  std::uint64_t dropped() const { return dropped_; }
  std::uint64_t bytes() const { return bytes_; }
  // A live output's status from these counts: connected while the last bundle went out.
  OutputStatus statusAs(std::string name) const;

 private:
  UdpEndpoint endpoint_;
  int socket_ = -1;
  std::vector<unsigned char> address_;  // sockaddr_storage bytes
  unsigned addressLength_ = 0;
  std::uint64_t sent_ = 0, dropped_ = 0, bytes_ = 0;
  bool lastSent_ = false;
};

}  // namespace th::outputs
