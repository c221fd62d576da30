#include "formats/animation_format.h"

#include <cmath>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/text_files.h"
#include "formats/text_tokens.h"

namespace th::formats {

void AnimationFormat::check(const std::filesystem::path&, const face::FapTrack&) const {}

face::FapTrack AnimationFormat::read(std::string_view, const std::filesystem::path& path) const {
  throw fileError(path, "the " + std::string(name()) + " format is written, not read");
}

const std::vector<const AnimationFormat*>& animationFormats() {
  static const std::vector<const AnimationFormat*> formats{
      &csvFormat(),        &jsonFormat(),       &fapStreamFormat(),   &arkitFormat(),
      &oculusFormat(),     &oculusJsonFormat(), &vrmFormat(),         &vrmJsonFormat(),
      &rhubarbTsvFormat(), &rhubarbXmlFormat(), &rhubarbJsonFormat(), &mohoFormat()};
  return formats;
}

const AnimationFormat& animationFormat(std::string_view name) {
  std::string names;
  for (const AnimationFormat* format : animationFormats()) {
    if (format->name() == name) return *format;
    names += (names.empty() ? "" : ", ") + std::string(format->name());
  }
  throw Error("no animation format \"" + printable(name) + "\" (there are " + names + ")");
}

const AnimationFormat& animationFormatFor(const std::filesystem::path& path) {
  const std::string extension = lowercaseExtension(path);
  for (const AnimationFormat* format : animationFormats())
    if (format->readable() && format->extension() == extension) return *format;
  const std::string given = path.extension().string();
  throw fileError(path,
                  (given.empty() ? std::string("has no extension") : "has the extension '" + printable(given) + "'") +
                      "; an animation file is .csv, .json or .fap");
}

const AnimationFormat& formatForWriting(const std::filesystem::path& path, std::string_view name) {
  const std::string extension = lowercaseExtension(path);
  if (!name.empty()) {
    const AnimationFormat& named = animationFormat(name);
    if (extension == ".json" && named.extension() != ".json")
      for (const AnimationFormat* format : animationFormats())
        if (format->name() == std::string(name) + "-json") return *format;
    return named;
  }
  std::string extensions;
  for (const AnimationFormat* format : animationFormats()) {
    if (format->extension() == extension) return *format;
    if (extensions.find(format->extension()) == std::string::npos)
      extensions += (extensions.empty() ? "" : ", ") + std::string(format->extension());
  }
  const std::string given = path.extension().string();
  throw fileError(path,
                  (given.empty() ? std::string("has no extension") : "has the extension '" + printable(given) + "'") +
                      "; an animation is written as " + extensions + " (or name a format with --format)");
}

void checkTrack(const std::filesystem::path& path, const face::FapTrack& track) {
  const double fps = track.framesPerSecond;
  if (!(std::isfinite(fps) && fps > 0))
    throw fileError(path, "the frame rate " + formatNumber(fps) + " fps is not positive and finite");
  const std::vector<int>& faps = track.faps;
  for (std::size_t r = 0; r < faps.size(); ++r) {
    if (faps[r] < 1 || faps[r] > face::kNumFaps)
      throw fileError(path,
                      "FAP number " + std::to_string(faps[r]) + " is outside 1.." + std::to_string(face::kNumFaps));
    if (r > 0 && faps[r] <= faps[r - 1])
      throw fileError(path, "FAP " + std::to_string(faps[r]) + " follows FAP " + std::to_string(faps[r - 1]) +
                                ": the FAP numbers must be ascending and unique");
  }
  if (track.values.rows() != static_cast<Eigen::Index>(faps.size()))
    throw fileError(path, "the values have " + std::to_string(track.values.rows()) + " rows, but the track lists " +
                              counted(faps.size(), "FAP"));
  if (track.numFrames() == 0) throw fileError(path, "the animation has no frames");
  for (int f = 0; f < track.numFrames(); ++f)
    for (std::size_t r = 0; r < faps.size(); ++r) {
      const double value = track.values(static_cast<Eigen::Index>(r), f);
      if (!std::isfinite(value))
        throw fileError(path, "frame " + std::to_string(f) + ", " + fapColumnName(faps[r]) + " is " +
                                  formatNumber(value) + ": values must be finite");
    }
}

void writeAnimation(const std::filesystem::path& path, const face::FapTrack& track) {
  writeAnimation(path, track, animationFormatFor(path));
}

void writeAnimation(const std::filesystem::path& path, const face::FapTrack& track, const AnimationFormat& format) {
  checkTrack(path, track);
  format.check(path, track);
  AtomicFile file(path);
  format.write(file.stream(), track);
  file.commit();
}

face::FapTrack readAnimation(const std::filesystem::path& path) {
  const AnimationFormat& format = animationFormatFor(path);
  const std::string text = readTextFile(path, "animation file");
  face::FapTrack track = format.read(text, path);
  checkTrack(path, track);
  format.check(path, track);
  return track;
}

}  // namespace th::formats
