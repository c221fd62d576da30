// A folder of one's own talking videos tracked for training (`train --video`, `train head --video`).
//
//   const auto tracks = tracksFolderFor(output, arguments.tracks);   // default: beside the output, NAME_tracks
//   tracking::VideoCorpus corpus = trackVideos(tracking::listVideos(folder), tracks, options);
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "tracking/video_training.h"

namespace th::app {

// `given`, else the output's name without its extension and with "_tracks" added.
std::filesystem::path tracksFolderFor(const std::filesystem::path& output, const std::string& given);

// The videos tracked and fitted with the default face model, their tracks kept (and re-used) in `tracks`
// (options.trackFolder is set to it), a progress bar counting clips on stderr. A tracks folder made by this call
// is removed again when the tracking fails.
tracking::VideoCorpus trackVideos(const std::vector<std::filesystem::path>& videos, const std::filesystem::path& tracks,
                                  tracking::VideoCorpusOptions options);

}  // namespace th::app
