// Rhubarb Lip Sync's output formats, byte for byte as Rhubarb writes them (its README's "Output formats" and
// its exporters): TSV, XML, JSON, and Moho's switch data (.dat, which Moho and OpenToonz read), so that a
// Rhubarb user can swap the program and keep the rest of the pipeline. The cues: mouth_cues.h.
#include <cmath>
#include <ostream>
#include <string>

#include "core/error.h"
#include "formats/animation_format.h"
#include "formats/mouth_cues.h"

namespace th::formats {
namespace {

std::string escapedXml(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string escapedJson(const std::string& text) {
  std::string out;
  char code[8];
  for (char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      std::snprintf(code, sizeof code, "\\u%04x", static_cast<unsigned>(c));
      out += code;
    } else {
      out += c;
    }
  }
  return out;
}

class CueFormat : public AnimationFormat {
 public:
  void check(const std::filesystem::path& path, const face::FapTrack& track) const override {
    checkVisemes(path, track);
    if (durationCentiseconds(track) < 1) throw fileError(path, "the animation is shorter than 0.01 s");
  }
};

class RhubarbTsvFormat final : public CueFormat {
 public:
  std::string_view name() const override { return "rhubarb-tsv"; }
  std::string_view extension() const override { return ".tsv"; }
  std::string_view description() const override {
    return "Rhubarb's mouth cues A-H, X: a start time and a shape per line";
  }
  void write(std::ostream& out, const face::FapTrack& track) const override {
    for (const MouthCue& cue : mouthCues(track)) out << centiseconds(cue.startCs) << '\t' << cue.shape << '\n';
    out << centiseconds(durationCentiseconds(track)) << '\t' << 'X' << '\n';
  }
};

class RhubarbXmlFormat final : public CueFormat {
 public:
  std::string_view name() const override { return "rhubarb-xml"; }
  std::string_view extension() const override { return ".xml"; }
  std::string_view description() const override { return "Rhubarb's mouth cues as its XML (rhubarbResult)"; }
  void write(std::ostream& out, const face::FapTrack& track) const override {
    out << "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<rhubarbResult>\n  <metadata>\n    <soundFile>"
        << escapedXml(track.source) << "</soundFile>\n    <duration>" << centiseconds(durationCentiseconds(track))
        << "</duration>\n  </metadata>\n  <mouthCues>\n";
    for (const MouthCue& cue : mouthCues(track))
      out << "    <mouthCue start=\"" << centiseconds(cue.startCs) << "\" end=\"" << centiseconds(cue.endCs) << "\">"
          << cue.shape << "</mouthCue>\n";
    out << "  </mouthCues>\n</rhubarbResult>\n";
  }
};

class RhubarbJsonFormat final : public CueFormat {
 public:
  std::string_view name() const override { return "rhubarb-json"; }
  std::string_view extension() const override { return ".json"; }
  std::string_view description() const override { return "Rhubarb's mouth cues as its JSON (metadata, mouthCues)"; }
  void write(std::ostream& out, const face::FapTrack& track) const override {
    out << "{\n  \"metadata\": {\n    \"soundFile\": \"" << escapedJson(track.source)
        << "\",\n    \"duration\": " << centiseconds(durationCentiseconds(track)) << "\n  },\n  \"mouthCues\": [\n";
    bool first = true;
    for (const MouthCue& cue : mouthCues(track)) {
      if (!first) out << ",\n";
      first = false;
      out << "    { \"start\": " << centiseconds(cue.startCs) << ", \"end\": " << centiseconds(cue.endCs)
          << ", \"value\": \"" << cue.shape << "\" }";
    }
    out << "\n  ]\n}\n";
  }
};

// Moho's switch data at Rhubarb's default 24 frames a second: "MohoSwitch1", then "FRAME SHAPE" lines from frame
// 1, a shape only where its frame differs from the last one written, and the rest shape at the end.
class MohoFormat final : public CueFormat {
 public:
  static constexpr double kFramesPerSecond = 24.0;
  std::string_view name() const override { return "moho"; }
  std::string_view extension() const override { return ".dat"; }
  std::string_view description() const override {
    return "Moho/OpenToonz switch data at 24 fps (Rhubarb's .dat, shapes A-H, X)";
  }
  void write(std::ostream& out, const face::FapTrack& track) const override {
    const auto frameOf = [](int cs) { return 1 + static_cast<int>(kFramesPerSecond * cs / 100.0); };
    out << "MohoSwitch1\n";
    int last = 0;
    for (const MouthCue& cue : mouthCues(track)) {
      const int frame = frameOf(cue.startCs);
      if (frame == last) continue;
      out << frame << ' ' << cue.shape << '\n';
      last = frame;
    }
    int frame = frameOf(durationCentiseconds(track));
    if (frame == last) ++frame;
    out << frame << ' ' << 'X' << '\n';
  }
};

}  // namespace

const AnimationFormat& rhubarbTsvFormat() {
  static const RhubarbTsvFormat format;
  return format;
}
const AnimationFormat& rhubarbXmlFormat() {
  static const RhubarbXmlFormat format;
  return format;
}
const AnimationFormat& rhubarbJsonFormat() {
  static const RhubarbJsonFormat format;
  return format;
}
const AnimationFormat& mohoFormat() {
  static const MohoFormat format;
  return format;
}

}  // namespace th::formats
