/* Live use from C: a WAV file's samples pushed into a stream in 10 ms blocks, as a sound card would deliver them,
 * and the frames pulled as they become ready. Prints one line a second: the jaw (ARKit jawOpen), the viseme shown
 * and the head's yaw.
 *
 *   stream speech.wav            (16-bit PCM WAV, any rate, mono or the first channel) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <talkinghead/talkinghead.h>

/* A minimal reader of 16-bit PCM WAV files: the samples of the first channel, as floats. */
static float* read_wav(const char* path, size_t* count, double* rate) {
  FILE* file = fopen(path, "rb");
  if (!file) return NULL;
  unsigned char header[12], chunk[8];
  int channels = 0, bits = 0;
  float* samples = NULL;
  if (fread(header, 1, 12, file) != 12 || memcmp(header, "RIFF", 4) || memcmp(header + 8, "WAVE", 4)) goto done;
  while (fread(chunk, 1, 8, file) == 8) {
    const unsigned long size = chunk[4] | chunk[5] << 8 | chunk[6] << 16 | (unsigned long)chunk[7] << 24;
    if (!memcmp(chunk, "fmt ", 4)) {
      unsigned char fmt[16];
      if (size < 16 || fread(fmt, 1, 16, file) != 16) goto done;
      channels = fmt[2] | fmt[3] << 8;
      *rate = fmt[4] | fmt[5] << 8 | fmt[6] << 16 | (unsigned long)fmt[7] << 24;
      bits = fmt[14] | fmt[15] << 8;
      fseek(file, (long)(size - 16 + (size & 1)), SEEK_CUR);
    } else if (!memcmp(chunk, "data", 4) && channels > 0 && bits == 16) {
      const size_t frames = size / (2u * (unsigned)channels);
      short* pcm = malloc(size);
      samples = malloc(frames * sizeof *samples);
      if (!pcm || !samples || fread(pcm, 1, size, file) != size) {
        free(pcm);
        free(samples);
        samples = NULL;
        goto done;
      }
      for (size_t i = 0; i < frames; ++i) samples[i] = pcm[i * (size_t)channels] / 32768.0f;
      free(pcm);
      *count = frames;
      goto done;
    } else {
      fseek(file, (long)(size + (size & 1)), SEEK_CUR);
    }
  }
done:
  fclose(file);
  return samples;
}

static void show(const th_frame* frame, int* next_second) {
  if (frame->time_seconds + 1e-9 < *next_second) return;
  printf("%5.2f s  jawOpen %.2f  viseme %-3s  shape %c  yaw %+5.1f deg\n", frame->time_seconds, frame->arkit[17],
         frame->viseme >= 0 ? th_viseme_name(frame->viseme) : "-", frame->rhubarb_shape, frame->head_yaw_deg);
  ++*next_second;
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
  th_models* models = NULL; /* the installed models */
  th_stream_settings settings;
  th_stream_settings_init(&settings);
  settings.sample_rate_hz = rate;
  th_stream* stream = NULL;
  if (th_models_load(NULL, &models) != TH_OK || th_stream_start(models, &settings, &stream) != TH_OK) {
    fprintf(stderr, "%s\n", th_last_error());
    th_models_free(models);
    free(samples);
    return 1;
  }
  th_models_free(models); /* the stream keeps what it uses */
  printf("libtalkinghead %s: %s, %.0f Hz, frames %.0f ms after their sound\n", th_version(), argv[1], rate,
         th_stream_latency_ms(stream));
  const size_t block = (size_t)(rate / 100.0);
  th_frame frame;
  th_frame_init(&frame);
  int frames = 0, next_second = 0;
  for (size_t at = 0; at < count; at += block) {
    const size_t n = count - at < block ? count - at : block;
    if (th_stream_push(stream, samples + at, n) != TH_OK) break;
    while (th_stream_pull(stream, &frame) == 1) {
      show(&frame, &next_second);
      ++frames;
    }
  }
  th_stream_finish(stream);
  while (th_stream_pull(stream, &frame) == 1) {
    show(&frame, &next_second);
    ++frames;
  }
  printf("%d frames for %.2f s of sound\n", frames, (double)count / rate);
  th_stream_close(stream);
  free(samples);
  return frames > 0 ? 0 : 1;
}
