// A folder of one's own talking videos tracked for training (`train --video`, `train head --video`).
//
//   const auto tracks = th::tracking::tracksFolderFor(output, given);   // default: beside the output, NAME_tracks
//   th::tracking::VideoCorpus corpus =
//       th::tracking::trackVideos(th::tracking::listVideos(folder), tracks, {}, std::cerr);
//
// Thread contract: one call at a time (the tracking runs on threads of its own).
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "tracking/video_training.h"

namespace th::tracking {

// `given`, else the output's name without its extension and with "_tracks" added.
std::filesystem::path tracksFolderFor(const std::filesystem::path& output, const std::string& given);

// The videos tracked and fitted with the default face model, their tracks kept (and re-used) in `tracks`
// (options.trackFolder is set to it), a progress bar counting clips on `log`. A tracks folder made by this call
// is removed again when the tracking fails.
VideoCorpus trackVideos(const std::vector<std::filesystem::path>& videos, const std::filesystem::path& tracks,
                        VideoCorpusOptions options, std::ostream& log);

}  // namespace th::tracking
