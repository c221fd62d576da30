// A decoded FFmpeg picture as an 8-bit BGR cv::Mat, converted by libswscale (bicubic, as OpenCV's FFmpeg back-end
// converts): shared by the video reader and the camera. Include only from .cpp files that link FFmpeg.
//
//   th::tracking::BgrConverter converter;
//   cv::Mat bgr;
//   if (converter.convert(*frame, bgr)) use(bgr);   // a new image each call, never shared with the last
//
// Thread contract: one thread per converter.
#pragma once

extern "C" {
#include <libavutil/frame.h>
#include <libavutil/macros.h>
#include <libswscale/swscale.h>
}

#include <cstdint>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <vector>

#include "core/ffmpeg_support.h"

namespace th::tracking {

class BgrConverter {
 public:
  // false for a picture without a size or in a format swscale cannot read.
  bool convert(const AVFrame& frame, cv::Mat& bgr) {
    const int width = frame.width, height = frame.height;
    if (width <= 0 || height <= 0) return false;
    scaler_.reset(sws_getCachedContext(scaler_.release(), width, height, static_cast<AVPixelFormat>(frame.format),
                                       width, height, AV_PIX_FMT_BGR24, SWS_BICUBIC, nullptr, nullptr, nullptr));
    if (!scaler_) return false;
    // swscale's vector code may write a little past a row's end: its rows get an aligned stride and the buffer a
    // tail of its own, and the picture is copied out of it.
    const int stride = FFALIGN(3 * width, 64);
    converted_.resize(static_cast<std::size_t>(stride) * static_cast<std::size_t>(height) + 64);
    std::uint8_t* planes[4] = {converted_.data(), nullptr, nullptr, nullptr};
    int strides[4] = {stride, 0, 0, 0};
    sws_scale(scaler_.get(), frame.data, frame.linesize, 0, height, planes, strides);
    bgr = cv::Mat(height, width, CV_8UC3, converted_.data(), static_cast<std::size_t>(stride)).clone();
    return true;
  }

 private:
  ffmpeg::ScalerHandle scaler_;
  std::vector<std::uint8_t> converted_;  // swscale's output, rows at an aligned stride
};

}  // namespace th::tracking
