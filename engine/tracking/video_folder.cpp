#include "tracking/video_folder.h"

#include <system_error>

#include "core/progress.h"
#include "face/face_model.h"

namespace th::tracking {

std::filesystem::path tracksFolderFor(const std::filesystem::path& output, const std::string& given) {
  if (!given.empty()) return given;
  return std::filesystem::path(output).replace_extension().string() + "_tracks";
}

VideoCorpus trackVideos(const std::vector<std::filesystem::path>& videos, const std::filesystem::path& tracks,
                        VideoCorpusOptions options, std::ostream& log) {
  options.trackFolder = tracks;
  const face::FaceModel face = face::FaceModel::buildDefault();
  std::error_code error;
  const bool tracksExisted = std::filesystem::exists(tracks, error);
  try {
    ProgressOptions clipCount;
    clipCount.unitsPerSecond = 0.0;  // clips, not seconds of media: no real-time factor
    ProgressBar bar(static_cast<double>(videos.size()), "track", log, clipCount);
    VideoCorpus corpus = loadVideoCorpus(videos, face, options, [&](int done, int) { bar.update(done); });
    bar.finish();
    return corpus;
  } catch (...) {
    if (!tracksExisted) std::filesystem::remove(tracks, error);  // made for this run and still empty
    throw;
  }
}

}  // namespace th::tracking
