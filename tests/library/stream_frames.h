// A stream's frames through libtalkinghead's C API, for the library's tests: the samples pushed in blocks, every
// frame pulled, then the end, then the stream closed; and two runs' frames compared byte for byte.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <vector>

#include "talkinghead/talkinghead.h"

namespace th::test {

inline std::vector<th_frame> pullAllFrames(th_stream* stream, const std::vector<float>& samples, std::size_t block) {
  std::vector<th_frame> frames;
  th_frame frame;
  th_frame_init(&frame);
  for (std::size_t at = 0; at < samples.size(); at += block) {
    EXPECT_EQ(th_stream_push(stream, samples.data() + at, std::min(block, samples.size() - at)), TH_OK);
    while (th_stream_pull(stream, &frame) == 1) frames.push_back(frame);
  }
  EXPECT_EQ(th_stream_finish(stream), TH_OK);
  while (th_stream_pull(stream, &frame) == 1) frames.push_back(frame);
  th_stream_close(stream);
  return frames;
}

inline void expectSameFrames(const std::vector<th_frame>& got, const std::vector<th_frame>& expected) {
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < got.size(); ++i)
    ASSERT_EQ(std::memcmp(&got[i], &expected[i], sizeof(th_frame)), 0) << "frame " << i;
}

}  // namespace th::test
