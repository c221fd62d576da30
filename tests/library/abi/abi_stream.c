/* A C program as one built against an older header would be: compiled twice, against the current header and
 * against tests/library/abi/talkinghead_0.2_first.h (th_stream_options and th_frame without the fields appended
 * since), both linked to the current library. It streams a recording and prints each frame's numbers, so that
 * the two runs can be compared; it checks that the library wrote nothing past the caller's struct and that the
 * frames are sane, and exits non-zero if not.
 *
 *   abi_stream SPEECH.wav > frames.txt */
#ifdef TH_ABI_FIRST
#include "talkinghead_0.2_first.h"
#else
#include "talkinghead/talkinghead.h"
#endif

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GUARD_BYTES 64
#define GUARD 0xA5

/* 16-bit PCM: the samples as floats (NULL for anything else). */
static float* read_wav(const char* path, size_t* count, double* rate) {
  FILE* file = fopen(path, "rb");
  if (!file) return NULL;
  unsigned char header[12], chunk[8];
  float* samples = NULL;
  if (fread(header, 1, 12, file) != 12 || memcmp(header, "RIFF", 4) != 0) goto done;
  while (fread(chunk, 1, 8, file) == 8) {
    const uint32_t size = chunk[4] | chunk[5] << 8 | chunk[6] << 16 | (uint32_t)chunk[7] << 24;
    if (memcmp(chunk, "fmt ", 4) == 0) {
      unsigned char format[16];
      if (size < 16 || fread(format, 1, 16, file) != 16) goto done;
      *rate = format[4] | format[5] << 8 | format[6] << 16 | (uint32_t)format[7] << 24;
      fseek(file, (long)(size - 16 + (size & 1)), SEEK_CUR);
    } else if (memcmp(chunk, "data", 4) == 0) {
      *count = size / 2;
      samples = malloc(*count * sizeof(float));
      for (size_t i = 0; samples && i < *count; ++i) {
        unsigned char two[2];
        if (fread(two, 1, 2, file) != 2) {
          *count = i;
          break;
        }
        samples[i] = (int16_t)(two[0] | two[1] << 8) / 32768.0f;
      }
      goto done;
    } else {
      fseek(file, (long)(size + (size & 1)), SEEK_CUR);
    }
  }
done:
  fclose(file);
  return samples;
}

static int intact(const unsigned char* guard) {
  for (int i = 0; i < GUARD_BYTES; ++i)
    if (guard[i] != GUARD) return 0;
  return 1;
}

/* Each struct with guard bytes after it, as far as the caller's header knows it. */
static struct {
  th_frame frame;
  unsigned char guard[GUARD_BYTES];
} slot;
static struct {
  th_stream_options options;
  unsigned char guard[GUARD_BYTES];
} given;

static int bad = 0;
static int frames = 0;

static void check(int ok, const char* what) {
  if (!ok && bad++ < 10) fprintf(stderr, "frame %d: %s\n", frames, what);
}

static void take(const th_frame* frame) {
  check(intact(slot.guard), "the library wrote past the caller's th_frame");
  check(frame->struct_size == sizeof(th_frame), "struct_size changed");
  check(frame->index == frames, "out of order");
  check(fabs(frame->time_seconds - frame->index / 30.0) < 1e-9, "its time is not index / 30");
  float sum = 0.0f;
  for (int k = 0; k < TH_NUM_ARKIT; ++k) check(frame->arkit[k] >= 0.0f && frame->arkit[k] <= 1.0f, "ARKit 0..1");
  for (int k = 0; k < TH_NUM_VISEMES; ++k) sum += frame->visemes[k];
  check(sum == 0.0f || fabsf(sum - 1.0f) < 1e-3f, "the visemes do not sum to 1");
  check(frame->viseme >= -1 && frame->viseme < TH_NUM_VISEMES, "viseme out of range");
  check(fabsf(frame->head_yaw_deg) < 90.0f, "head yaw");
  printf("%d %.6f %.6f %d %c %.5f %.5f %.5f\n", frame->index, frame->arkit[17], frame->faps[3], frame->viseme,
         frame->rhubarb_shape, frame->head_pitch_deg, frame->head_yaw_deg, frame->head_roll_deg);
  ++frames;
}

int main(int argc, char** argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: %s SPEECH.wav\n", argv[0]);
    return 2;
  }
  size_t count = 0;
  double rate = 0.0;
  float* samples = read_wav(argv[1], &count, &rate);
  if (!samples) {
    fprintf(stderr, "%s: not a 16-bit PCM WAV file\n", argv[1]);
    return 1;
  }
  memset(&given, GUARD, sizeof given);
  memset(&slot, GUARD, sizeof slot);
  if (th_stream_options_init(&given.options) != TH_OK || !intact(given.guard)) {
    fprintf(stderr, "th_stream_options_init: %s\n", intact(given.guard) ? th_last_error() : "wrote past the struct");
    return 1;
  }
  given.options.sample_rate_hz = rate;
  th_stream* stream = NULL;
  if (th_stream_open(&given.options, &stream) != TH_OK) {
    fprintf(stderr, "%s\n", th_last_error());
    return 1;
  }
  if (th_frame_init(&slot.frame) != TH_OK || !intact(slot.guard)) {
    fprintf(stderr, "th_frame_init: %s\n", intact(slot.guard) ? th_last_error() : "wrote past the struct");
    return 1;
  }
  const size_t block = 441;
  for (size_t at = 0; at < count; at += block) {
    if (th_stream_push(stream, samples + at, count - at < block ? count - at : block) != TH_OK) return 1;
    while (th_stream_pull(stream, &slot.frame) == 1) take(&slot.frame);
  }
  th_stream_finish(stream);
  while (th_stream_pull(stream, &slot.frame) == 1) take(&slot.frame);
  th_stream_close(stream);
  free(samples);
  const int expected = (int)(count / rate * 30.0);
  check(frames >= expected - 2 && frames <= expected + 2, "not 30 frames a second of sound");
  fprintf(stderr, "%d frames, th_frame %zu bytes, th_stream_options %zu bytes, library %s\n", frames, sizeof(th_frame),
          sizeof(th_stream_options), th_version());
  return bad == 0 ? 0 : 1;
}
