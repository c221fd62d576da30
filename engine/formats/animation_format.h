// Animation files: each format one class behind one small interface (as Rhubarb's exporters), and the
// functions that pick a format by name or by a file's extension.
//
//   th::formats::writeAnimation("out.fap", track);                        // by the extension: .csv .json .fap
//   th::face::FapTrack back = th::formats::readAnimation("out.csv");
//   th::formats::writeAnimation("weights.csv", track, th::formats::animationFormat("arkit"));
//
// The formats (docs/formats.md has their layouts):
//   csv    FAP curves, a row per frame (.csv)                           read and written
//   json   FAP curves with their names and units (.json)                read and written
//   fap    the MPEG-4 FAP stream Xface and Greta read (.fap)            read and written
//   arkit  Apple's 52 blendshape weights per frame (.csv)              written
// and, from the track's visemes (FapTrack::visemes, made by a viseme model; face/visemes.h):
//   oculus, oculus-json   Oculus/OpenXR's 15 viseme weights per frame (.csv, .json)          written
//   vrm, vrm-json         VRM's A I U E O weights per frame (.csv, .json)                     written
//   rhubarb-tsv, rhubarb-xml, rhubarb-json, moho
//                         Rhubarb Lip Sync's mouth cues in its layouts (.tsv, .xml, .json, .dat)   written
// A new format is one file (a class deriving from AnimationFormat) and a line in animation_format.cpp's list.
//
// Every write checks the track first (a positive finite frame rate, FAP numbers ascending, unique and in 1..68,
// finite values shaped to them, at least one frame) and is atomic: all or nothing. Every read applies the same
// checks to what it read, so whatever it returns writes back in its own format. Errors (th::Error) are one
// line that names the file and, when reading, the line or field and what is wrong.
// Thread contract: formats are immutable; the functions are pure functions of files.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string_view>
#include <vector>

#include "face/fap_track.h"

namespace th::formats {

class AnimationFormat {
 public:
  virtual ~AnimationFormat() = default;
  virtual std::string_view name() const = 0;         // "csv", "json", "fap", "arkit"
  virtual std::string_view extension() const = 0;    // the files' extension, ".csv"
  virtual std::string_view description() const = 0;  // one line, for --help and the docs
  virtual bool readable() const { return false; }
  // Beyond the common checks: throws th::Error naming `path` if the format cannot hold this track.
  virtual void check(const std::filesystem::path& path, const face::FapTrack& track) const;
  virtual void write(std::ostream& out, const face::FapTrack& track) const = 0;
  // Formats that read: the track in `text`, errors naming `path`. Others throw th::Error.
  virtual face::FapTrack read(std::string_view text, const std::filesystem::path& path) const;
};

// Every format, in the order above.
const std::vector<const AnimationFormat*>& animationFormats();
// By name; throws th::Error listing the names.
const AnimationFormat& animationFormat(std::string_view name);
// The readable format of a file's extension (case-insensitive); throws th::Error naming the file otherwise.
const AnimationFormat& animationFormatFor(const std::filesystem::path& path);
// What to write to `path`: the named format (empty: the first in the list above with the path's extension);
// a name with a JSON twin ("oculus", "vrm") takes the twin for a .json path. Throws th::Error naming the file
// or listing the names.
const AnimationFormat& formatForWriting(const std::filesystem::path& path, std::string_view name = {});

// The common checks (see above); throws th::Error naming `path`.
void checkTrack(const std::filesystem::path& path, const face::FapTrack& track);
// The viseme formats' own: the track has visemes on its frames.
void checkVisemes(const std::filesystem::path& path, const face::FapTrack& track);

void writeAnimation(const std::filesystem::path& path, const face::FapTrack& track);
void writeAnimation(const std::filesystem::path& path, const face::FapTrack& track, const AnimationFormat& format);
face::FapTrack readAnimation(const std::filesystem::path& path);

// The formats themselves (their files: csv_format.cpp, json_format.cpp, fap_stream_format.cpp,
// arkit_format.cpp, viseme_weight_formats.cpp, rhubarb_formats.cpp; arkit_format.h has the ARKit format with a
// face's own scale).
const AnimationFormat& csvFormat();
const AnimationFormat& jsonFormat();
const AnimationFormat& fapStreamFormat();
const AnimationFormat& arkitFormat();
const AnimationFormat& oculusFormat();
const AnimationFormat& oculusJsonFormat();
const AnimationFormat& vrmFormat();
const AnimationFormat& vrmJsonFormat();
const AnimationFormat& rhubarbTsvFormat();
const AnimationFormat& rhubarbXmlFormat();
const AnimationFormat& rhubarbJsonFormat();
const AnimationFormat& mohoFormat();

}  // namespace th::formats
