// FAP curves as CSV: a header `time_s,fap3,fap48,...` (the FAP columns in ascending order), then one row per
// frame; time_s is frame / fps. Reading takes the columns in any order and the frame rate from the time
// column (frames must be evenly spaced, so a file needs two of them).
#include <algorithm>
#include <array>
#include <cmath>
#include <ostream>

#include "core/error.h"
#include "core/text_files.h"
#include "formats/animation_format.h"
#include "formats/text_tokens.h"

namespace th::formats {
namespace {

namespace fs = std::filesystem;

// Decimals of a time: rounding moves a time by at most a tenth of the reader's spacing tolerance, so the
// reader recovers the frame rate (7 decimals at 25 and 30 fps).
int timeDecimals(double framesPerSecond) {
  const double needed = std::ceil(std::log10(framesPerSecond) + std::log10(0.5 / (0.1 * kSpacingTolerance)));
  return static_cast<int>(std::clamp(needed, 6.0, 340.0));
}

// The rate of evenly spaced times. Printed times are rounded (1/30 s has no exact decimal), so the rate from
// the first and last times is a little off the nominal one: a whole rate, a whole rate × 1000/1001 (NTSC
// video) or a rate with up to three decimals (12.5) is taken, in that order, when every time is within the
// tolerance of it.
double frameRateOf(const std::vector<double>& times, const std::vector<int>& lines, const fs::path& path) {
  const double span = times.back() - times.front();
  if (!(span > 0)) {
    failAt(path, lines.back(),
           "time_s " + formatNumber(times.back()) + " is not after the first row's " + formatNumber(times.front()) +
               ": time_s must increase");
  }
  const double measured = static_cast<double>(times.size() - 1) / span;
  if (!std::isfinite(measured)) failAt(path, lines.back(), "time_s steps are too short to give a frame rate");
  for (const double nominal :
       {std::round(measured), std::round(measured * 1.001) * 1000.0 / 1001.0, std::round(measured * 10.0) / 10.0,
        std::round(measured * 100.0) / 100.0, std::round(measured * 1000.0) / 1000.0}) {
    if (nominal > 0 && firstUnevenTime(times, nominal) == times.size()) return nominal;
  }
  if (const std::size_t i = firstUnevenTime(times, measured); i < times.size()) {
    failAt(path, lines[i],
           "time_s " + formatNumber(times[i]) + " breaks the even spacing of frames: at " + formatNumber(measured) +
               " fps (from the first and last rows) this row is at " +
               formatNumber(times[0] + static_cast<double>(i) / measured));
  }
  return measured;
}

// "fap48" → 48; 0 if the column name is not of that form.
int fapOfColumn(std::string_view name) {
  if (!name.starts_with("fap")) return 0;
  const auto number = parseInt(name.substr(3));
  return number && *number >= 1 && *number <= face::kNumFaps ? *number : 0;
}

class CsvFormat final : public AnimationFormat {
 public:
  std::string_view name() const override { return "csv"; }
  std::string_view extension() const override { return ".csv"; }
  std::string_view description() const override { return "FAP curves: time_s, then a column per FAP (fap3, ...)"; }
  bool readable() const override { return true; }

  void check(const fs::path& path, const face::FapTrack& track) const override {
    if (track.numFrames() == 1) {
      throw fileError(path,
                      "one frame: a CSV file gives its frame rate only through time_s, which takes two frames "
                      "(write .json or .fap)");
    }
    if (!std::isfinite((track.numFrames() - 1) / track.framesPerSecond))
      throw fileError(path, "at " + formatNumber(track.framesPerSecond) +
                                " fps the last frame's time is beyond the range of a double");
  }

  void write(std::ostream& out, const face::FapTrack& track) const override {
    out << "time_s";
    for (int fap : track.faps) out << ',' << fapColumnName(fap);
    out << '\n';
    const int decimals = timeDecimals(track.framesPerSecond);
    for (int f = 0; f < track.numFrames(); ++f) {
      out << fixedNotation(f / track.framesPerSecond, decimals);
      for (Eigen::Index r = 0; r < track.values.rows(); ++r) out << ',' << shortest(track.values(r, f));
      out << '\n';
    }
  }

  face::FapTrack read(std::string_view text, const fs::path& path) const override {
    TextLines lines(text);
    std::string_view line;
    if (!lines.nextContent(line, false)) throw fileError(path, "is empty (expected a header line time_s,fap3,...)");
    const int headerLine = lines.number();
    constexpr std::size_t kMaxColumns = 1 + face::kNumFaps;
    const Fields header = splitCommas(line, kMaxColumns);
    if (header.items[0] != "time_s") {
      if (parseNumber(header.items[0])) failAt(path, headerLine, "the header is missing: expected time_s,fap3,...");
      failAt(path, headerLine, "the first column is '" + printable(header.items[0]) + "'; expected time_s");
    }
    // Columns may come in any order; the track's are ascending.
    std::array<std::size_t, face::kNumFaps + 1> columnOfFap{};  // header column of each FAP, 0 if absent
    for (std::size_t c = 1; c < header.items.size(); ++c) {
      const int fap = fapOfColumn(header.items[c]);
      if (fap == 0) {
        failAt(path, headerLine,
               "column " + std::to_string(c + 1) + " '" + printable(header.items[c]) +
                   "' is not a FAP column (fap1 .. fap68)");
      }
      if (columnOfFap[static_cast<std::size_t>(fap)] != 0) {
        failAt(path, headerLine,
               "columns " + std::to_string(columnOfFap[static_cast<std::size_t>(fap)] + 1) + " and " +
                   std::to_string(c + 1) + " are both " + fapColumnName(fap));
      }
      columnOfFap[static_cast<std::size_t>(fap)] = c;
    }
    if (header.count > kMaxColumns) {
      failAt(path, headerLine,
             "the header has " + std::to_string(header.count) + " columns; there are only time_s and the 68 FAPs");
    }
    face::FapTrack track;
    for (int fap = 1; fap <= face::kNumFaps; ++fap)
      if (columnOfFap[static_cast<std::size_t>(fap)] != 0) track.faps.push_back(fap);

    std::vector<double> times;
    std::vector<double> values;  // frame after frame, in the track's FAP order
    std::vector<int> rowLines;
    std::array<double, kMaxColumns> row{};
    while (lines.nextContent(line, false)) {
      const Fields fields = splitCommas(line, header.count);
      if (fields.count != header.count) {
        failAt(path, lines.number(),
               counted(fields.count, "value") + ", but the header has " + counted(header.count, "column"));
      }
      for (std::size_t c = 0; c < fields.count; ++c) {
        const auto value = parseNumber(fields.items[c]);
        if (!value || !std::isfinite(*value)) {
          failAt(path, lines.number(),
                 std::string(header.items[c]) + " '" + printable(fields.items[c]) + "' is not a finite number");
        }
        row[c] = *value;
      }
      times.push_back(row[0]);
      for (int fap : track.faps) values.push_back(row[columnOfFap[static_cast<std::size_t>(fap)]]);
      rowLines.push_back(lines.number());
    }
    if (times.empty()) failAt(path, headerLine, "no frames follow the header");
    if (times.size() == 1) failAt(path, rowLines[0], "one frame: the frame rate cannot be derived from time_s");
    track.framesPerSecond = frameRateOf(times, rowLines, path);
    track.values = Eigen::Map<const Eigen::MatrixXd>(values.data(), static_cast<Eigen::Index>(track.faps.size()),
                                                     static_cast<Eigen::Index>(times.size()));
    return track;
  }
};

}  // namespace

const AnimationFormat& csvFormat() {
  static const CsvFormat format;
  return format;
}

}  // namespace th::formats
