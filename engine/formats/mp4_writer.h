// Writing rendered frames and their sound track as an MP4 file that plays everywhere: H.264 video (libx264,
// yuv420p, High profile) and AAC audio (FFmpeg's native encoder), through FFmpeg's libraries.
//
//   th::formats::Mp4Writer writer("talk.mp4", {.width = 1280, .height = 720, .framesPerSecond = 30.0});
//   writer.addAudio(clip.samples);                                  // 16 kHz mono float, any amount at a time
//   const int frames = th::formats::videoFramesFor(clip.samples.size(), 16000, 30.0);   // ceil(seconds * fps)
//   for (int f = 0; f < frames; ++f) writer.addVideoFrame(render(f).data(), 1280 * 3);   // RGB24, top row first
//   writer.finish();                                                // only now does talk.mp4 appear
//
// All or nothing: the file is written as an unnamed temporary file in the target's folder (Linux O_TMPFILE;
// where the file system lacks it, a hidden ".NAME.PID.N.tmp" beside the target) and named as the target only
// when finish() has written it completely, replacing an existing target in one step. A writer destroyed without
// finish() (an exception, a cancelled export) leaves no file behind and the old target untouched; so does a
// killed process when O_TMPFILE is available (the kernel frees the unnamed file).
//
// Timing: video frame f is shown from f / fps; audio sample n plays at n / audioSampleRateHz; both streams start
// at 0 (AAC's 1024-sample encoder priming is declared as the stream's initial padding and an MP4 edit list, so
// players and FFmpeg skip it). Audio and video may be given in any interleaving; each stream is in order.
// Unequal lengths: audio shorter than the video is padded with silence to the video's end (the sound track
// always covers the picture, and a file with no audio at all gets a silent track); audio longer than the video
// is kept whole (players hold the last frame until the sound ends; the file's duration is the audio's). So
// writing videoFramesFor(samples) frames makes the two streams equally long to within one sample.
//
// Colour: RGB is taken as full-range sRGB/BT.709 and converted by libswscale to limited-range ("TV") YUV with the
// BT.709 matrix for HD (height >= 720) and the BT.601 (SMPTE 170M) matrix below that, the matrices players
// assume for untagged video of those sizes; the stream is tagged accordingly (range, matrix, BT.709 primaries
// and transfer), so tag-aware players and ones that guess agree.
//
// Errors are one-line th::Error naming the target: bad options (odd or non-positive size, fps <= 0, ...),
// a missing or unwritable folder, an encoder missing from the FFmpeg build ("libx264 is not available in this
// FFmpeg build"), frames of the wrong stride, calls after finish() or after an earlier error, write failures.
// FFmpeg's own logging is switched off for the process (see core/ffmpeg_support.h).
// Thread contract: one thread per instance; libx264 runs its own worker threads (Mp4Options::threads).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>

namespace th::formats {

struct Mp4Options {
  int width = 1280;                 // even and positive (yuv420p halves both for colour)
  int height = 720;                 // even and positive
  double framesPerSecond = 30.0;    // positive; taken as the nearest rational (29.97 -> 2997/100)
  int audioSampleRateHz = 16000;    // rate of the mono float samples given to addAudio
  int outputAudioRateHz = 48000;    // the AAC stream's rate (one AAC supports: 8000 ... 96000)
  int audioBitRate = 96000;         // bits per second of AAC (mono)
  int crf = 20;                     // x264 constant quality, 0 (lossless) ... 51; lower is better and larger
  std::string preset = "veryfast";  // x264 speed/size trade-off: ultrafast ... placebo
  // Further x264 settings over the preset, "key=value:key=value" (FFmpeg's x264-params). For the program's own
  // use: libx264 ignores a name it does not know.
  std::string x264Params;
  int threads = 0;                       // x264 threads; 0: FFmpeg decides from the number of cores
  double keyframeIntervalSeconds = 5.0;  // longest gap between keyframes (seek points)
  bool unnamedTemporaryFile = true;      // false: always the hidden named temporary file (see above)
};

// A frame already in the video stream's own format, 8-bit Y'CbCr 4:2:0 in limited ("TV") range with the colour
// matrix Mp4Writer::usesBt709() names: for callers that convert colour themselves (the face export does it in
// the pass that finishes each frame), so the writer skips libswscale. Planes top row first; the chroma planes
// have (width + 1) / 2 x (height + 1) / 2 samples.
struct Yuv420Planes {
  const std::uint8_t* y = nullptr;
  int yStride = 0;
  const std::uint8_t* cb = nullptr;
  const std::uint8_t* cr = nullptr;
  int chromaStride = 0;
};

// Frames that cover `samples` of audio at `sampleRateHz`: ceil(samples / sampleRateHz * fps), computed exactly
// with the rational frame rate Mp4Writer uses (30 fps and 16000 samples make 30 frames, not 31).
std::int64_t videoFramesFor(std::size_t samples, int sampleRateHz, double framesPerSecond);

class Mp4Writer {
 public:
  // Checks the options and the target's folder, opens the temporary file and writes the header.
  Mp4Writer(std::filesystem::path target, const Mp4Options& options);
  // Without finish(): stops the encoders and deletes the temporary file; the target is left as it was.
  ~Mp4Writer();
  Mp4Writer(const Mp4Writer&) = delete;
  Mp4Writer& operator=(const Mp4Writer&) = delete;

  // One width x height RGB24 frame, top row first, rows strideBytes apart (at least width * 3). A bottom-up
  // buffer (glReadPixels) can be given as a pointer to its last row with a negative stride.
  void addVideoFrame(const std::uint8_t* rgb, int strideBytes);
  // The same, checking that the frame lies within `rgb` (rows strideBytes apart, strideBytes > 0).
  void addVideoFrame(std::span<const std::uint8_t> rgb, int strideBytes);
  // One frame as Y'CbCr planes (see Yuv420Planes), rows at least width (luma) and width / 2 (chroma) long.
  void addVideoFrame(const Yuv420Planes& planes);
  // Mono samples at audioSampleRateHz, nominally in [-1, 1]; any amount at a time, in order. Must be finite.
  void addAudio(std::span<const float> mono);
  // Flushes the encoders, pads the audio (see above), writes the index at the front of the file (faststart)
  // and renames the file onto the target. Needs at least one video frame. Throws th::Error naming the target.
  void finish();

  int framesWritten() const;
  // The colour matrix of the stream (its tags, the RGB conversion, and what Yuv420Planes must hold): BT.709 for
  // heights of 720 and more, else BT.601.
  bool usesBt709() const;
  double videoSeconds() const;  // framesWritten() / fps
  double audioSeconds() const;  // of the samples given to addAudio so far
  const std::filesystem::path& target() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace th::formats
