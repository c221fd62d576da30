/* Every frame libtalkinghead's stream gives for a recording, every field at full precision, one line each: what
 * tools/output_fingerprints.sh compares between two builds of the library. The samples are pushed in 10 ms
 * blocks, as a sound card would deliver them, and the frames pulled after each block.
 *
 *   library_frames SPEECH.wav WAIT_FOR_HEAD(0|1) > frames.txt */
#include <sndfile.h>
#include <stdio.h>
#include <stdlib.h>
#include <talkinghead/talkinghead.h>

static void print_floats(const float* values, int count) {
  for (int i = 0; i < count; ++i) printf(" %.9g", values[i]);
}

static void print_frame(const th_frame* frame) {
  printf("%d %.9g", frame->index, frame->time_seconds);
  print_floats(frame->faps + 1, TH_NUM_FAPS);
  print_floats(frame->arkit, TH_NUM_ARKIT);
  print_floats(frame->visemes, TH_NUM_VISEMES);
  print_floats(frame->vrm, TH_NUM_VRM);
  printf(" %d %c %.9g %.9g %.9g", frame->viseme, frame->rhubarb_shape, frame->head_pitch_deg, frame->head_yaw_deg,
         frame->head_roll_deg);
  print_floats(frame->head_rotation_unity, 4);
  printf("\n");
}

int main(int argc, char** argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: %s SPEECH.wav WAIT_FOR_HEAD(0|1)\n", argv[0]);
    return 2;
  }
  SF_INFO info = {0};
  SNDFILE* file = sf_open(argv[1], SFM_READ, &info);
  if (!file) {
    fprintf(stderr, "%s: %s\n", argv[1], sf_strerror(NULL));
    return 1;
  }
  const sf_count_t frames = info.frames;
  float* interleaved = malloc((size_t)frames * (size_t)info.channels * sizeof *interleaved);
  float* samples = malloc((size_t)frames * sizeof *samples);
  if (!interleaved || !samples || sf_readf_float(file, interleaved, frames) != frames) {
    fprintf(stderr, "%s: could not read its samples\n", argv[1]);
    return 1;
  }
  sf_close(file);
  for (sf_count_t i = 0; i < frames; ++i) samples[i] = interleaved[i * info.channels];
  free(interleaved);

  th_stream_options options;
  th_stream_options_init(&options);
  options.sample_rate_hz = info.samplerate;
  options.wait_for_head = atoi(argv[2]);
  th_stream* stream = NULL;
  if (th_stream_open(&options, &stream) != TH_OK) {
    fprintf(stderr, "%s\n", th_last_error());
    return 1;
  }
  printf("latency %.9g ms\n", th_stream_latency_ms(stream));
  th_frame frame;
  th_frame_init(&frame);
  const size_t block = (size_t)(info.samplerate / 100);
  for (size_t at = 0; at < (size_t)frames; at += block) {
    const size_t count = at + block <= (size_t)frames ? block : (size_t)frames - at;
    if (th_stream_push(stream, samples + at, count) != TH_OK) {
      fprintf(stderr, "%s\n", th_last_error());
      return 1;
    }
    while (th_stream_pull(stream, &frame) == 1) print_frame(&frame);
  }
  th_stream_finish(stream);
  while (th_stream_pull(stream, &frame) == 1) print_frame(&frame);
  th_stream_close(stream);
  free(samples);
  return 0;
}
