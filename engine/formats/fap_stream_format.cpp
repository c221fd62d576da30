// The MPEG-4 FAP stream that Xface and Greta read (.fap): a header line `2.1 NAME FPS NFRAMES`, then per frame
// a mask line of 68 `0`/`1` flags (FAP 1..68) and a line with the frame number and the integer values of the
// flagged FAPs in FAP order. Writing rounds values to integers and flags every FAP of the track in every
// frame. Reading accepts masks that change between frames: a FAP not sent in a frame holds its last value
// (0 before it is first sent), and the track's FAPs are every FAP sent at least once. Blank lines and lines
// starting with '#' are skipped.
#include <bitset>
#include <cmath>
#include <cstdint>
#include <ostream>

#include "core/error.h"
#include "core/text_files.h"
#include "formats/animation_format.h"
#include "formats/text_tokens.h"

namespace th::formats {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kFapVersion = "2.1";
// Xface and Greta read values as 32-bit ints; a value is written only if its rounding fits one.
constexpr double kFapValueBelow = -2147483648.5;
constexpr double kFapValueAbove = 2147483647.5;

// The header's NAME is one whitespace-free token.
std::string headerName(const std::string& name) {
  if (name.empty()) return face::FapTrack{}.name;
  std::string token = name;
  for (char& c : token) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte <= 0x20 || byte == 0x7f) c = '_';
  }
  return token;
}

class FapStreamFormat final : public AnimationFormat {
 public:
  std::string_view name() const override { return "fap"; }
  std::string_view extension() const override { return ".fap"; }
  std::string_view description() const override { return "MPEG-4 FAP stream (Xface, Greta): masks and integer values"; }
  bool readable() const override { return true; }

  void check(const fs::path& path, const face::FapTrack& track) const override {
    for (int f = 0; f < track.numFrames(); ++f)
      for (std::size_t r = 0; r < track.faps.size(); ++r) {
        const double value = track.values(static_cast<Eigen::Index>(r), f);
        if (!(value > kFapValueBelow && value < kFapValueAbove))
          throw fileError(path, "frame " + std::to_string(f) + ", " + fapColumnName(track.faps[r]) + " is " +
                                    formatNumber(value) + ": a .fap holds 32-bit integer values");
      }
  }

  void write(std::ostream& out, const face::FapTrack& track) const override {
    // Shortest fixed notation: "30" for a whole rate, "29.97" otherwise; readers expect no exponent.
    out << kFapVersion << ' ' << headerName(track.name) << ' ' << fixedNotation(track.framesPerSecond) << ' '
        << track.numFrames() << '\n';
    // Every FAP in every frame, so the mask is the same line each time.
    std::string mask;
    for (int fap = 1; fap <= face::kNumFaps; ++fap) {
      mask += fap > 1 ? " " : "";
      mask += track.rowOf(fap) >= 0 ? '1' : '0';
    }
    for (int f = 0; f < track.numFrames(); ++f) {
      out << mask << '\n' << f;
      for (Eigen::Index r = 0; r < track.values.rows(); ++r) out << ' ' << std::lround(track.values(r, f));
      out << '\n';
    }
  }

  face::FapTrack read(std::string_view text, const fs::path& path) const override {
    TextLines lines(text);
    std::string_view line;
    if (!lines.nextContent(line, true))
      throw fileError(path, "is empty (expected a header line `2.1 NAME FPS NFRAMES`)");
    const int headerLine = lines.number();
    face::FapTrack track;
    // Only compared with the frames read, never used to size anything: a forged header costs nothing.
    const long long announced = readFapHeader(line, path, headerLine, track);

    // Kept as sent (masks and the values they flag) and filled in at the end, once the FAPs are known.
    SentFrames sent;
    long long previousFrame = -1;
    while (lines.nextContent(line, true)) {
      const int maskLine = lines.number();
      if (static_cast<long long>(sent.masks.size()) == announced) {
        failAt(path, maskLine,
               "a frame beyond the " + std::to_string(announced) + " that the header on line " +
                   std::to_string(headerLine) + " announces");
      }
      const std::bitset<face::kNumFaps> mask = readFapMask(line, path, maskLine);
      if (!lines.nextContent(line, true))
        failAt(path, maskLine, "the file ends after this mask; expected a line with the frame number and values");
      readFapValues(line, path, {.maskLine = maskLine, .valueLine = lines.number()}, mask, previousFrame, sent);
    }
    if (sent.masks.empty()) failAt(path, headerLine, "no frames follow the header");
    if (static_cast<long long>(sent.masks.size()) != announced) {
      failAt(path, headerLine,
             "the header announces " + std::to_string(announced) + " frames, but the file has " +
                 std::to_string(sent.masks.size()));
    }
    fillHeldValues(sent, track);
    return track;
  }

 private:
  struct SentFrames {
    std::vector<std::bitset<face::kNumFaps>> masks;
    std::vector<std::int32_t> values;  // the flagged FAPs' values, frame after frame
    std::bitset<face::kNumFaps> everSent;
  };
  struct FrameLines {
    int maskLine = 0, valueLine = 0;
  };

  // `2.1 NAME FPS NFRAMES` into the track's name and rate; returns NFRAMES.
  static long long readFapHeader(std::string_view line, const fs::path& path, int headerLine, face::FapTrack& track) {
    const Fields header = splitWhitespace(line, 4);
    if (header.count != 4) {
      failAt(path, headerLine,
             "the header `2.1 NAME FPS NFRAMES` is missing: this line has " + std::to_string(header.count) + " fields");
    }
    if (header.items[0] != kFapVersion) {
      failAt(path, headerLine,
             "version '" + printable(header.items[0]) + "' is not 2.1 (the header is `2.1 NAME FPS NFRAMES`)");
    }
    track.name = std::string(header.items[1]);
    const auto fps = parseNumber(header.items[2]);
    if (!fps || !std::isfinite(*fps) || *fps <= 0)
      failAt(path, headerLine, "the frame rate '" + printable(header.items[2]) + "' is not a positive number");
    track.framesPerSecond = *fps;
    const auto announced = parseLong(header.items[3]);
    if (!announced || *announced < 0)
      failAt(path, headerLine,
             "the frame count '" + printable(header.items[3]) + "' is not a whole number (0 or more)");
    return *announced;
  }

  static std::bitset<face::kNumFaps> readFapMask(std::string_view line, const fs::path& path, int maskLine) {
    const Fields flags = splitWhitespace(line, face::kNumFaps);
    if (flags.count != face::kNumFaps)
      failAt(path, maskLine, "the mask has " + std::to_string(flags.count) + " flags; expected 68 (a 0 or 1 per FAP)");
    std::bitset<face::kNumFaps> mask;
    for (std::size_t i = 0; i < flags.items.size(); ++i) {
      if (flags.items[i] == "1") {
        mask.set(i);
      } else if (flags.items[i] != "0") {
        failAt(path, maskLine,
               "mask flag " + std::to_string(i + 1) + " is '" + printable(flags.items[i]) + "'; expected 0 or 1");
      }
    }
    return mask;
  }

  // The frame number, after the last one, and the values the mask flags.
  static void readFapValues(std::string_view line, const fs::path& path, FrameLines at,
                            const std::bitset<face::kNumFaps>& mask, long long& previousFrame, SentFrames& sent) {
    const Fields items = splitWhitespace(line, mask.count() + 1);
    if (items.count != mask.count() + 1) {
      failAt(path, at.valueLine,
             "the frame number is followed by " + counted(items.count - 1, "value") + ", but the mask on line " +
                 std::to_string(at.maskLine) + " flags " + counted(mask.count(), "FAP"));
    }
    const auto frame = parseLong(items.items[0]);
    if (!frame || *frame < 0) {
      failAt(path, at.valueLine,
             "the frame number '" + printable(items.items[0]) + "' is not a whole number (0 or more)");
    }
    if (*frame <= previousFrame) {
      failAt(path, at.valueLine,
             "frame number " + std::to_string(*frame) + " follows " + std::to_string(previousFrame) +
                 ": frame numbers must increase");
    }
    previousFrame = *frame;
    std::size_t item = 1;
    for (std::size_t i = 0; i < mask.size(); ++i) {
      if (!mask.test(i)) continue;
      const std::string_view token = items.items[item++];
      const auto value = parseInt(token);
      if (!value) {
        failAt(path, at.valueLine,
               fapColumnName(static_cast<int>(i) + 1) + " '" + printable(token) + "' is not a 32-bit integer");
      }
      sent.values.push_back(*value);
    }
    sent.masks.push_back(mask);
    sent.everSent |= mask;
  }

  // The track's FAPs are those ever sent; a FAP not sent in a frame holds its last value, 0 before it is first sent.
  static void fillHeldValues(const SentFrames& sent, face::FapTrack& track) {
    for (std::size_t i = 0; i < sent.everSent.size(); ++i)
      if (sent.everSent.test(i)) track.faps.push_back(static_cast<int>(i) + 1);
    std::array<double, face::kNumFaps> current{};
    track.values.resize(static_cast<Eigen::Index>(track.faps.size()), static_cast<Eigen::Index>(sent.masks.size()));
    std::size_t next = 0;
    for (std::size_t f = 0; f < sent.masks.size(); ++f) {
      for (std::size_t i = 0; i < sent.masks[f].size(); ++i)
        if (sent.masks[f].test(i)) current[i] = sent.values[next++];
      for (std::size_t r = 0; r < track.faps.size(); ++r)
        track.values(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(f)) =
            current[static_cast<std::size_t>(track.faps[r] - 1)];
    }
  }
};

}  // namespace

const AnimationFormat& fapStreamFormat() {
  static const FapStreamFormat format;
  return format;
}

}  // namespace th::formats
