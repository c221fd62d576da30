#include "formats/mp4_writer.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/channel_layout.h>
#include <libavutil/dict.h>
#include <libavutil/mathematics.h>
#include <libavutil/opt.h>
#include <libavutil/rational.h>
#include <libswresample/swresample.h>
#include <libswscale/swscale.h>
}

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/ffmpeg_support.h"
#include "core/pending_file.h"

#if LIBAVUTIL_VERSION_INT < AV_VERSION_INT(57, 24, 100)
#error "mp4_writer.cpp needs FFmpeg 5.1 or later (AVChannelLayout, swr_alloc_set_opts2)"
#endif

namespace th::formats {
namespace {

namespace fs = std::filesystem;
using ffmpeg::CodecHandle;
using ffmpeg::FrameHandle;
using ffmpeg::PacketHandle;

// FFmpeg's error codes, spelled once (its macros contain C casts).
const int kEndOfFile = AVERROR_EOF;
const int kTryAgain = AVERROR(EAGAIN);

constexpr int kMaxSide = 16384;  // H.264 level 6.2's widest picture is 8192; anything past this is a bug
constexpr double kMaxFramesPerSecond = 1000.0;
constexpr int kMinInputRateHz = 1000;
constexpr int kMaxInputRateHz = 768000;
constexpr std::size_t kAudioBlock = 16384;  // input samples resampled at a time (bounds the buffers)
constexpr int kHdHeight = 720;              // from this height on, BT.709; below it BT.601

const char* const kX264Presets[] = {"ultrafast", "superfast", "veryfast", "faster",   "fast",
                                    "medium",    "slow",      "slower",   "veryslow", "placebo"};

struct ResamplerFreer {
  void operator()(SwrContext* context) const { swr_free(&context); }
};
using ffmpeg::OutputHandle;
using ffmpeg::ScalerHandle;
using ResamplerHandle = std::unique_ptr<SwrContext, ResamplerFreer>;

using ffmpeg::Dictionary;

using ffmpeg::frameRateOf;

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", value);
  return text;
}

void checkOptions(const fs::path& target, const Mp4Options& options) {
  const auto fail = [&](const std::string& what) { return fileError(target, what); };
  if (options.width <= 0 || options.height <= 0 || options.width > kMaxSide || options.height > kMaxSide) {
    throw fail("the video size " + std::to_string(options.width) + "x" + std::to_string(options.height) +
               " is not positive and at most " + std::to_string(kMaxSide) + " on each side");
  }
  if (options.width % 2 != 0 || options.height % 2 != 0) {
    throw fail("the video size " + std::to_string(options.width) + "x" + std::to_string(options.height) +
               " is odd (H.264 in yuv420p needs an even width and height)");
  }
  if (!std::isfinite(options.framesPerSecond) || options.framesPerSecond <= 0.0 ||
      options.framesPerSecond > kMaxFramesPerSecond) {
    throw fail("the frame rate " + number(options.framesPerSecond) + " is not in (0, " + number(kMaxFramesPerSecond) +
               "] frames per second");
  }
  const AVRational rate = frameRateOf(options.framesPerSecond);
  if (rate.num <= 0 || rate.den <= 0) {
    throw fail("the frame rate " + number(options.framesPerSecond) + " has no usable fraction");
  }
  if (options.audioSampleRateHz < kMinInputRateHz || options.audioSampleRateHz > kMaxInputRateHz) {
    throw fail("the audio sample rate " + std::to_string(options.audioSampleRateHz) + " Hz is outside " +
               std::to_string(kMinInputRateHz) + "-" + std::to_string(kMaxInputRateHz) + " Hz");
  }
  if (options.audioBitRate < 8000 || options.audioBitRate > 512000) {
    throw fail("the audio bit rate " + std::to_string(options.audioBitRate) + " is outside 8000-512000 bits/s");
  }
  if (options.crf < 0 || options.crf > 51) {
    throw fail("the x264 quality (crf) " + std::to_string(options.crf) + " is outside 0-51");
  }
  if (std::find(std::begin(kX264Presets), std::end(kX264Presets), options.preset) == std::end(kX264Presets)) {
    throw fail("unknown x264 preset \"" + options.preset +
               "\" (ultrafast, superfast, veryfast, faster, fast, medium, slow, slower, veryslow, placebo)");
  }
  if (options.threads < 0 || options.threads > 256) {
    throw fail("the number of encoder threads " + std::to_string(options.threads) + " is outside 0-256");
  }
  if (!std::isfinite(options.keyframeIntervalSeconds) || options.keyframeIntervalSeconds <= 0.0 ||
      options.keyframeIntervalSeconds > 3600.0) {
    throw fail("the keyframe interval " + number(options.keyframeIntervalSeconds) + " s is not in (0, 3600] seconds");
  }
}

// An encoder of the build, or a th::Error that says which one is missing.
const AVCodec* requireEncoder(const fs::path& target, const char* name, const char* what) {
  const AVCodec* codec = avcodec_find_encoder_by_name(name);
  if (codec == nullptr) throw fileError(target, std::string(what) + " is not available in this FFmpeg build");
  return codec;
}

bool supportsRate(const AVCodec& codec, int rateHz) {
  if (codec.supported_samplerates == nullptr) return true;
  for (const int* rate = codec.supported_samplerates; *rate != 0; ++rate) {
    if (*rate == rateHz) return true;
  }
  return false;
}

}  // namespace

std::int64_t videoFramesFor(std::size_t samples, int sampleRateHz, double framesPerSecond) {
  if (sampleRateHz <= 0 || !std::isfinite(framesPerSecond) || framesPerSecond <= 0.0) {
    throw Error("videoFramesFor: the sample rate and frame rate must be positive");
  }
  const AVRational rate = frameRateOf(framesPerSecond);
  // samples * num / (rateHz * den), rounded up, without overflow for any plausible length.
  return av_rescale_rnd(static_cast<std::int64_t>(samples), rate.num,
                        static_cast<std::int64_t>(sampleRateHz) * rate.den, AV_ROUND_UP);
}

struct Mp4Writer::State {
  enum class Status { kOpen, kFinished, kFailed };

  State(fs::path targetPath, const Mp4Options& writerOptions)
      : target(std::move(targetPath)), options(writerOptions), frameRate(frameRateOf(options.framesPerSecond)) {}

  fs::path target;
  Mp4Options options;
  AVRational frameRate;
  std::unique_ptr<PendingFile> file;  // declared before the FFmpeg objects: closed after them
  OutputHandle output;
  CodecHandle video;
  CodecHandle audio;
  AVStream* videoStream = nullptr;
  AVStream* audioStream = nullptr;
  ScalerHandle scaler;
  ResamplerHandle resampler;
  FrameHandle picture;
  PacketHandle packet;
  std::vector<float> resampled;  // output-rate samples not yet encoded, from resampledStart on
  std::size_t resampledStart = 0;
  std::vector<float> resampleBuffer;
  std::int64_t framesIn = 0;
  std::int64_t audioSamplesIn = 0;   // at the input rate
  std::int64_t audioSamplesOut = 0;  // at the output rate, given to the AAC encoder
  Status status = Status::kOpen;

  Error failure(const std::string& what) const { return fileError(target, what); }
  Error failure(const std::string& what, int code) const {
    return fileError(target, what + " (FFmpeg: " + ffmpeg::message(code) + ")");
  }

  void open();
  void openVideo(const AVCodec& encoder);
  void openAudio(const AVCodec& encoder);
  void encodePicture(const std::uint8_t* rgb, int strideBytes);
  void encodePlanes(const Yuv420Planes& planes);
  void sendPicture();
  void resample(const float* samples, std::size_t count);
  void encodeAudio(bool final);
  void send(AVCodecContext& codec, AVStream& stream, const AVFrame* frame, const char* what);
  void complete();
};

void Mp4Writer::State::open() {
  ffmpeg::silenceLogging();
  checkOptions(target, options);
  const AVCodec* videoEncoder = requireEncoder(target, "libx264", "libx264");
  const AVCodec* audioEncoder = requireEncoder(target, "aac", "FFmpeg's AAC encoder (aac)");
  if (!supportsRate(*audioEncoder, options.outputAudioRateHz)) {
    throw failure("AAC does not support the audio sample rate " + std::to_string(options.outputAudioRateHz) +
                  " Hz (use 8000, 11025, 12000, 16000, 22050, 24000, 32000, 44100, 48000, 64000, 88200 or "
                  "96000)");
  }
  checkOutputTarget(target);
  std::error_code ignored;
  const fs::file_status existing = fs::status(target, ignored);
  if (fs::exists(existing) && !fs::is_regular_file(existing)) {
    throw failure("is not a regular file (a device, pipe or socket): not replaced");
  }
  file = std::make_unique<PendingFile>(target, options.unnamedTemporaryFile);
  const std::string url = file->url();

  AVFormatContext* raw = nullptr;
  int result = avformat_alloc_output_context2(&raw, nullptr, "mp4", url.c_str());
  if (result < 0 || raw == nullptr) throw failure("cannot set up the MP4 muxer", result);
  output.reset(raw);
  openVideo(*videoEncoder);
  openAudio(*audioEncoder);

  result = avio_open(&output->pb, url.c_str(), AVIO_FLAG_WRITE);
  if (result < 0) throw failure("cannot be written", result);
  Dictionary muxerOptions;
  // The index (moov) goes in front of the data once everything is written, so playback starts before the
  // whole file has arrived; the muxer does that by rewriting the file at the end.
  av_dict_set(&muxerOptions.entries, "movflags", "+faststart", 0);
  // Edit-list and track durations are counted in the movie's time scale: FFmpeg's default of 1000 rounds the
  // streams' lengths to milliseconds; the audio rate makes them exact for the audio and common frame rates.
  av_dict_set_int(&muxerOptions.entries, "movie_timescale", options.outputAudioRateHz, 0);
  result = avformat_write_header(output.get(), &muxerOptions.entries);
  if (result < 0) throw failure("cannot write the MP4 header", result);

  packet.reset(av_packet_alloc());
  if (!packet) throw failure("out of memory");
}

void Mp4Writer::State::openVideo(const AVCodec& encoder) {
  video.reset(avcodec_alloc_context3(&encoder));
  if (!video) throw failure("out of memory");
  const bool hd = options.height >= kHdHeight;
  AVCodecContext& codec = *video;
  codec.width = options.width;
  codec.height = options.height;
  codec.pix_fmt = AV_PIX_FMT_YUV420P;
  codec.time_base = av_inv_q(frameRate);
  codec.framerate = frameRate;
  codec.sample_aspect_ratio = AVRational{1, 1};
  codec.gop_size = std::max(1, static_cast<int>(std::lround(options.keyframeIntervalSeconds * av_q2d(frameRate))));
  codec.thread_count = options.threads;
  codec.color_range = AVCOL_RANGE_MPEG;
  codec.colorspace = hd ? AVCOL_SPC_BT709 : AVCOL_SPC_SMPTE170M;
  codec.color_primaries = AVCOL_PRI_BT709;
  codec.color_trc = AVCOL_TRC_BT709;
  if ((output->oformat->flags & AVFMT_GLOBALHEADER) != 0) codec.flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  av_opt_set(codec.priv_data, "preset", options.preset.c_str(), 0);
  av_opt_set_double(codec.priv_data, "crf", options.crf, 0);
  if (!options.x264Params.empty() && av_opt_set(codec.priv_data, "x264-params", options.x264Params.c_str(), 0) < 0)
    throw failure("cannot pass the x264 settings \"" + options.x264Params + "\"");
  // Lossless coding (crf 0) needs the High 4:4:4 Predictive profile; everything else is plain High.
  if (options.crf > 0) av_opt_set(codec.priv_data, "profile", "high", 0);
  int result = avcodec_open2(&codec, &encoder, nullptr);
  if (result < 0) throw failure("cannot open the H.264 encoder (libx264)", result);

  videoStream = avformat_new_stream(output.get(), nullptr);
  if (videoStream == nullptr) throw failure("out of memory");
  videoStream->time_base = codec.time_base;
  videoStream->avg_frame_rate = frameRate;
  result = avcodec_parameters_from_context(videoStream->codecpar, &codec);
  if (result < 0) throw failure("cannot set up the video stream", result);

  scaler.reset(sws_getContext(options.width, options.height, AV_PIX_FMT_RGB24, options.width, options.height,
                              AV_PIX_FMT_YUV420P, SWS_BILINEAR, nullptr, nullptr, nullptr));
  if (!scaler) throw failure("cannot set up the RGB to YUV conversion");
  // Full-range RGB in; limited-range YUV out with the matrix the stream is tagged with.
  const int* matrix = sws_getCoefficients(hd ? SWS_CS_ITU709 : SWS_CS_SMPTE170M);
  if (sws_setColorspaceDetails(scaler.get(), matrix, 1, matrix, 0, 0, 1 << 16, 1 << 16) < 0) {
    throw failure("cannot set up the RGB to YUV conversion's colour space");
  }
  picture.reset(av_frame_alloc());
  if (!picture) throw failure("out of memory");
  picture->format = AV_PIX_FMT_YUV420P;
  picture->width = options.width;
  picture->height = options.height;
  picture->color_range = codec.color_range;
  picture->colorspace = codec.colorspace;
  picture->color_primaries = codec.color_primaries;
  picture->color_trc = codec.color_trc;
  result = av_frame_get_buffer(picture.get(), 0);
  if (result < 0) throw failure("out of memory for a video frame", result);
}

void Mp4Writer::State::openAudio(const AVCodec& encoder) {
  audio.reset(avcodec_alloc_context3(&encoder));
  if (!audio) throw failure("out of memory");
  AVCodecContext& codec = *audio;
  codec.sample_fmt = AV_SAMPLE_FMT_FLTP;
  codec.sample_rate = options.outputAudioRateHz;
  av_channel_layout_default(&codec.ch_layout, 1);
  codec.bit_rate = options.audioBitRate;
  codec.time_base = AVRational{1, options.outputAudioRateHz};
  if ((output->oformat->flags & AVFMT_GLOBALHEADER) != 0) codec.flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  int result = avcodec_open2(&codec, &encoder, nullptr);
  if (result < 0) throw failure("cannot open the AAC encoder", result);

  audioStream = avformat_new_stream(output.get(), nullptr);
  if (audioStream == nullptr) throw failure("out of memory");
  audioStream->time_base = codec.time_base;
  result = avcodec_parameters_from_context(audioStream->codecpar, &codec);
  if (result < 0) throw failure("cannot set up the audio stream", result);
  // The encoder's priming samples (1024 for AAC): its packets start at -initial_padding, and the muxer writes
  // an edit list that starts playback after them, so the first sample given plays at time 0.
  audioStream->codecpar->initial_padding = codec.initial_padding;

  SwrContext* raw = nullptr;
  AVChannelLayout mono{};
  av_channel_layout_default(&mono, 1);
  result = swr_alloc_set_opts2(&raw, &mono, AV_SAMPLE_FMT_FLTP, options.outputAudioRateHz, &mono, AV_SAMPLE_FMT_FLT,
                               options.audioSampleRateHz, 0, nullptr);
  av_channel_layout_uninit(&mono);
  resampler.reset(raw);
  if (result < 0 || !resampler) throw failure("cannot set up the audio resampler", result);
  result = swr_init(resampler.get());
  if (result < 0) throw failure("cannot set up the audio resampler", result);
}

// Sends one frame (nullptr: the end of the stream) and writes every packet the encoder has ready.
void Mp4Writer::State::send(AVCodecContext& codec, AVStream& stream, const AVFrame* frame, const char* what) {
  int result = avcodec_send_frame(&codec, frame);
  if (result < 0) throw failure(std::string(what) + " encoding failed", result);
  for (;;) {
    result = avcodec_receive_packet(&codec, packet.get());
    if (result == kTryAgain || result == kEndOfFile) return;
    if (result < 0) throw failure(std::string(what) + " encoding failed", result);
    av_packet_rescale_ts(packet.get(), codec.time_base, stream.time_base);
    packet->stream_index = stream.index;
    result = av_interleaved_write_frame(output.get(), packet.get());  // takes the packet's data
    if (result < 0) throw failure("write failed", result);
  }
}

void Mp4Writer::State::encodePicture(const std::uint8_t* rgb, int strideBytes) {
  int result = av_frame_make_writable(picture.get());
  if (result < 0) throw failure("out of memory for a video frame", result);
  const std::uint8_t* const source[] = {rgb, nullptr, nullptr, nullptr};
  const int sourceStride[] = {strideBytes, 0, 0, 0};
  const int rows = sws_scale(scaler.get(), source, sourceStride, 0, options.height, picture->data, picture->linesize);
  if (rows != options.height) throw failure("the RGB to YUV conversion failed", rows < 0 ? rows : 0);
  sendPicture();
}

void Mp4Writer::State::encodePlanes(const Yuv420Planes& planes) {
  int result = av_frame_make_writable(picture.get());
  if (result < 0) throw failure("out of memory for a video frame", result);
  const auto copyPlane = [](const std::uint8_t* from, int fromStride, std::uint8_t* to, int toStride, int width,
                            int height) {
    for (int row = 0; row < height; ++row)
      std::copy_n(from + static_cast<std::ptrdiff_t>(row) * fromStride, width,
                  to + static_cast<std::ptrdiff_t>(row) * toStride);
  };
  const int chromaWidth = (options.width + 1) / 2;
  const int chromaHeight = (options.height + 1) / 2;
  copyPlane(planes.y, planes.yStride, picture->data[0], picture->linesize[0], options.width, options.height);
  copyPlane(planes.cb, planes.chromaStride, picture->data[1], picture->linesize[1], chromaWidth, chromaHeight);
  copyPlane(planes.cr, planes.chromaStride, picture->data[2], picture->linesize[2], chromaWidth, chromaHeight);
  sendPicture();
}

void Mp4Writer::State::sendPicture() {
  picture->pts = framesIn;
  send(*video, *videoStream, picture.get(), "video");
  ++framesIn;
}

// Appends the resampled form of `count` samples (none: drains the resampler's delay line) to `resampled`.
void Mp4Writer::State::resample(const float* samples, std::size_t count) {
  const int inCount = static_cast<int>(count);
  const int room = swr_get_out_samples(resampler.get(), inCount);
  if (room < 0) throw failure("audio resampling failed", room);
  resampleBuffer.resize(static_cast<std::size_t>(room) + 1);
  std::uint8_t* out[] = {reinterpret_cast<std::uint8_t*>(resampleBuffer.data())};
  const std::uint8_t* in[] = {reinterpret_cast<const std::uint8_t*>(samples)};
  const int made = swr_convert(resampler.get(), out, room + 1, samples != nullptr ? in : nullptr, inCount);
  if (made < 0) throw failure("audio resampling failed", made);
  resampled.insert(resampled.end(), resampleBuffer.begin(), resampleBuffer.begin() + made);
}

// Encodes the resampled samples in the encoder's frame size; `final` also sends the last, shorter frame.
void Mp4Writer::State::encodeAudio(bool final) {
  const auto frameSize = static_cast<std::size_t>(audio->frame_size > 0 ? audio->frame_size : 1024);
  while (resampled.size() - resampledStart >= frameSize || (final && resampled.size() > resampledStart)) {
    const std::size_t count = std::min(frameSize, resampled.size() - resampledStart);
    FrameHandle frame(av_frame_alloc());
    if (!frame) throw failure("out of memory");
    frame->format = AV_SAMPLE_FMT_FLTP;
    frame->sample_rate = audio->sample_rate;
    frame->nb_samples = static_cast<int>(count);
    int result = av_channel_layout_copy(&frame->ch_layout, &audio->ch_layout);
    if (result >= 0) result = av_frame_get_buffer(frame.get(), 0);
    if (result < 0) throw failure("out of memory for an audio frame", result);
    std::copy_n(resampled.begin() + static_cast<std::ptrdiff_t>(resampledStart), count,
                reinterpret_cast<float*>(frame->data[0]));
    frame->pts = audioSamplesOut;
    send(*audio, *audioStream, frame.get(), "audio");
    resampledStart += count;
    audioSamplesOut += static_cast<std::int64_t>(count);
  }
  resampled.erase(resampled.begin(), resampled.begin() + static_cast<std::ptrdiff_t>(resampledStart));
  resampledStart = 0;
}

void Mp4Writer::State::complete() {
  if (framesIn == 0) throw failure("no video frames were added");
  resample(nullptr, 0);  // the resampler's last samples
  // Audio shorter than the video: silence up to the video's end (frames / fps at the output rate).
  const std::int64_t videoSamples = av_rescale_rnd(
      framesIn, static_cast<std::int64_t>(options.outputAudioRateHz) * frameRate.den, frameRate.num, AV_ROUND_NEAR_INF);
  const std::int64_t haveSamples = audioSamplesOut + static_cast<std::int64_t>(resampled.size() - resampledStart);
  if (haveSamples < videoSamples)
    resampled.resize(resampled.size() + static_cast<std::size_t>(videoSamples - haveSamples), 0.0F);
  encodeAudio(true);
  send(*audio, *audioStream, nullptr, "audio");
  send(*video, *videoStream, nullptr, "video");
  int result = av_write_trailer(output.get());
  if (result < 0) throw failure("cannot finish the MP4 file", result);
  if (output->pb != nullptr && output->pb->error < 0) throw failure("write failed", output->pb->error);
  result = avio_closep(&output->pb);
  if (result < 0) throw failure("write failed", result);
  file->commit();
}

Mp4Writer::Mp4Writer(fs::path target, const Mp4Options& options)
    : state_(std::make_unique<State>(std::move(target), options)) {
  state_->open();
}

Mp4Writer::~Mp4Writer() = default;

void Mp4Writer::addVideoFrame(const std::uint8_t* rgb, int strideBytes) {
  State& s = *state_;
  if (s.status == State::Status::kFinished) throw s.failure("a video frame was added after finish()");
  if (s.status == State::Status::kFailed) throw s.failure("a video frame was added after an earlier error");
  if (rgb == nullptr) throw s.failure("a video frame without pixels (null pointer)");
  const long long rowBytes = 3LL * s.options.width;
  if (std::llabs(static_cast<long long>(strideBytes)) < rowBytes) {
    throw s.failure("a video frame's rows are " + std::to_string(strideBytes) + " bytes apart, less than the " +
                    std::to_string(rowBytes) + " bytes of a " + std::to_string(s.options.width) + "-pixel RGB row");
  }
  try {
    s.encodePicture(rgb, strideBytes);
  } catch (...) {
    s.status = State::Status::kFailed;
    throw;
  }
}

void Mp4Writer::addVideoFrame(const Yuv420Planes& planes) {
  State& s = *state_;
  if (s.status == State::Status::kFinished) throw s.failure("a video frame was added after finish()");
  if (s.status == State::Status::kFailed) throw s.failure("a video frame was added after an earlier error");
  if (planes.y == nullptr || planes.cb == nullptr || planes.cr == nullptr)
    throw s.failure("a video frame without pixels (null pointer)");
  if (planes.yStride < s.options.width || planes.chromaStride < (s.options.width + 1) / 2)
    throw s.failure("a Y'CbCr frame's rows are " + std::to_string(planes.yStride) + " and " +
                    std::to_string(planes.chromaStride) + " bytes apart, less than its " +
                    std::to_string(s.options.width) + "-pixel rows need");
  try {
    s.encodePlanes(planes);
  } catch (...) {
    s.status = State::Status::kFailed;
    throw;
  }
}

bool Mp4Writer::usesBt709() const {
  return state_->options.height >= kHdHeight;
}

void Mp4Writer::addVideoFrame(std::span<const std::uint8_t> rgb, int strideBytes) {
  const State& s = *state_;
  const std::size_t rowBytes = 3 * static_cast<std::size_t>(s.options.width);
  if (strideBytes > 0 && static_cast<std::size_t>(strideBytes) >= rowBytes) {
    const std::size_t needed =
        static_cast<std::size_t>(strideBytes) * static_cast<std::size_t>(s.options.height - 1) + rowBytes;
    if (rgb.size() < needed) {
      throw s.failure("a video frame of " + std::to_string(rgb.size()) + " bytes is smaller than the " +
                      std::to_string(needed) + " bytes of " + std::to_string(s.options.width) + "x" +
                      std::to_string(s.options.height) + " RGB rows " + std::to_string(strideBytes) + " bytes apart");
    }
  } else if (strideBytes <= 0) {
    throw s.failure("a video frame given as a span needs a positive stride, not " + std::to_string(strideBytes));
  }
  addVideoFrame(rgb.data(), strideBytes);
}

void Mp4Writer::addAudio(std::span<const float> mono) {
  State& s = *state_;
  if (s.status == State::Status::kFinished) throw s.failure("audio was added after finish()");
  if (s.status == State::Status::kFailed) throw s.failure("audio was added after an earlier error");
  for (std::size_t n = 0; n < mono.size(); ++n) {
    if (!std::isfinite(mono[n])) {
      throw s.failure("audio sample " + std::to_string(s.audioSamplesIn + static_cast<std::int64_t>(n)) +
                      " is not a finite number (NaN or infinity)");
    }
  }
  try {
    for (std::size_t start = 0; start < mono.size(); start += kAudioBlock) {
      const std::size_t count = std::min(kAudioBlock, mono.size() - start);
      s.resample(mono.data() + start, count);
      s.audioSamplesIn += static_cast<std::int64_t>(count);
      s.encodeAudio(false);
    }
  } catch (...) {
    s.status = State::Status::kFailed;
    throw;
  }
}

void Mp4Writer::finish() {
  State& s = *state_;
  if (s.status == State::Status::kFinished) throw s.failure("finish() was called twice");
  if (s.status == State::Status::kFailed) throw s.failure("cannot finish after an earlier error");
  try {
    s.complete();
  } catch (...) {
    s.status = State::Status::kFailed;
    throw;
  }
  s.status = State::Status::kFinished;
}

int Mp4Writer::framesWritten() const {
  return static_cast<int>(state_->framesIn);
}

double Mp4Writer::videoSeconds() const {
  return static_cast<double>(state_->framesIn) / av_q2d(state_->frameRate);
}

double Mp4Writer::audioSeconds() const {
  return static_cast<double>(state_->audioSamplesIn) / state_->options.audioSampleRateHz;
}

const fs::path& Mp4Writer::target() const {
  return state_->target;
}

}  // namespace th::formats
