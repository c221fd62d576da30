/* FROZEN: libtalkinghead's header as a program built before the last fields were appended saw it, kept for
 * tests/library/abi: th_stream_options and th_frame of their first version (0.2, without the progress callback
 * and the Unity rotation), and none of the functions that came with those fields. Never edit it to follow the
 * current header; it is what an older program was compiled with. */
#ifndef TALKINGHEAD_ABI_FIRST_H
#define TALKINGHEAD_ABI_FIRST_H

#include <stddef.h>

#define TALKINGHEAD_VERSION_MAJOR 0
#define TALKINGHEAD_VERSION_MINOR 2
#define TALKINGHEAD_VERSION_PATCH 0
#define TALKINGHEAD_VERSION "0.2.0"

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__)
#define TH_API __attribute__((visibility("default")))
#else
#define TH_API
#endif

typedef enum th_status {
  TH_OK = 0,
  TH_ERROR_ARGUMENT = 1, /* a null pointer, a rate or option out of range */
  TH_ERROR_FILE = 2,     /* a file that cannot be read or written, or is not what it should be */
  TH_ERROR_STATE = 3,    /* a call out of order: pushing after th_stream_finish */
  TH_ERROR_INTERNAL = 4, /* anything else (out of memory) */
  TH_ERROR_CANCELLED = 5 /* a progress callback asked to stop: no output was made */
} th_status;

/* "0.2.0": the library's version (compare with the TALKINGHEAD_VERSION_* it was compiled against). */
TH_API const char* th_version(void);
/* The message of the last failure on this thread ("" if none); valid until the next call that fails. */
TH_API const char* th_last_error(void);

enum {
  TH_NUM_FAPS = 68,    /* FAPs 1..68: th_frame.faps[n] is FAP n (faps[0] unused) */
  TH_NUM_ARKIT = 52,   /* th_arkit_name(i) */
  TH_NUM_VISEMES = 15, /* th_viseme_name(i): sil PP FF TH DD kk CH SS nn RR aa E ih oh ou */
  TH_NUM_VRM = 5       /* th_vrm_name(i): A I U E O */
};

typedef struct th_frame {
  size_t struct_size;  /* sizeof(th_frame) as the caller was compiled: th_frame_init */
  int index;           /* from 0, 30 a second */
  double time_seconds; /* index / 30: the instant of the speech it shows */
  float faps[TH_NUM_FAPS + 1];
  float arkit[TH_NUM_ARKIT];     /* each 0..1 */
  float visemes[TH_NUM_VISEMES]; /* the Oculus visemes' probabilities, summing to 1 (all 0 before the first) */
  float vrm[TH_NUM_VRM];         /* each 0..1 */
  int viseme;                    /* the Oculus viseme shown, or -1 before the first is decided */
  char rhubarb_shape;            /* Rhubarb Lip Sync's shape for it: 'A'..'H' or 'X' */
  float head_pitch_deg;          /* down + */
  float head_yaw_deg;            /* to the speaker's left + */
  float head_roll_deg;           /* to the right + */
} th_frame;

/* The _init calls are macros that pass the struct's size as the caller was compiled: the library fills only that
 * much (each returns TH_ERROR_ARGUMENT for NULL or a size below the struct's first version). */
#define th_frame_init(frame) th_frame_init_sized((frame), sizeof(th_frame))
TH_API th_status th_frame_init_sized(th_frame* frame, size_t struct_size);

typedef struct th_stream_options {
  size_t struct_size;       /* sizeof(th_stream_options) as the caller was compiled: th_stream_options_init */
  const char* head_model;   /* a model file; NULL: the installed one; "": no head motion */
  const char* mouth_model;  /* NULL: the installed live model; "": no mouth */
  const char* viseme_model; /* NULL: the installed articulation's visemes (lips closed by the same classes);
                               a file: that viseme model's, without the articulation; "": no visemes */
  double sample_rate_hz;    /* of the pushed samples, 8000..192000 (default 16000) */
  int wait_for_head;        /* 0: frames as soon as the mouth is decided (the head shown its own look-ahead
                               late); 1: each frame waits for its own head (th_stream_latency_ms says how long) */
} th_stream_options;

/* The defaults: the installed models, 16000 Hz, frames not waiting for the head, no callback. */
#define th_stream_options_init(options) th_stream_options_init_sized((options), sizeof(th_stream_options))
TH_API th_status th_stream_options_init_sized(th_stream_options* options, size_t struct_size);

typedef struct th_stream th_stream;

TH_API th_status th_stream_open(const th_stream_options* options, th_stream** stream);
TH_API th_status th_stream_push(th_stream* stream, const float* samples, size_t count);
TH_API th_status th_stream_finish(th_stream* stream);
/* 1: a frame was written to *frame; 0: none is ready yet (push more, or finish); -1: an error. */
TH_API int th_stream_pull(th_stream* stream, th_frame* frame);
/* How far past a frame's instant the input must reach before the frame is out, ms. */
TH_API double th_stream_latency_ms(const th_stream* stream);
TH_API void th_stream_close(th_stream* stream);

typedef struct th_animation th_animation;

/* A whole recording (WAV, FLAC, OGG, MP3, or a video's sound) animated offline: the best the models do, with
 * the whole recording to look at. options: the models (NULL for the installed ones; its rate is ignored) and a
 * progress callback, called when the work starts and when it ends (the offline animation is one step). */
TH_API th_status th_animate_file(const char* recording, const th_stream_options* options, th_animation** animation);
TH_API int th_animation_frames(const th_animation* animation);
TH_API th_status th_animation_frame(const th_animation* animation, int index, th_frame* frame);
/* Any format `talkinghead animate` writes: format NULL picks it by the extension (.csv .json .fap .tsv .xml
 * .dat), or one of th_format_name(i). Written atomically: the file is whole or absent. */
TH_API th_status th_animation_write(const th_animation* animation, const char* path, const char* format);
/* The animation on a character: `avatar` (a glTF .glb/.gltf or VRM file with ARKit, Oculus-viseme or VRM morph
 * targets, and neck, head and eye bones) written to `path` (.glb, .gltf, or .vrm from a .vrm character) with the
 * speech as one more glTF animation, "speech": its mouth's morph target weights and its bones' rotations, 30
 * keyframes a second, as `talkinghead animate --avatar` writes it. animation_only non-zero: the animation alone
 * (.glb or .gltf), with the character's node hierarchy and morph target names but no meshes, for tools that
 * retarget by name. Written atomically: the file is whole or absent. */
TH_API th_status th_animation_write_avatar(const th_animation* animation, const char* avatar, const char* path,
                                           int animation_only);
TH_API void th_animation_free(th_animation* animation);

/* A recording rendered to MP4 (H.264 + AAC, the face speaking it, off-screen), as `talkinghead export` does. All
 * or nothing: the file appears only when complete. */
TH_API th_status th_export_file(const char* recording, const char* mp4, int width, int height);
/* The same with the user's character instead of our face: a .glb, .gltf or .vrm file whose ARKit, Oculus viseme
 * or VRM morph targets and neck, head and eye bones the speech moves (avatar NULL: our face), as `talkinghead
 * export --avatar` does. A character that cannot be read, or has nothing the speech can move, fails with
 * TH_ERROR_FILE naming it, and no video is written. */
TH_API th_status th_export_file_avatar(const char* recording, const char* mp4, int width, int height,
                                       const char* avatar);

TH_API const char* th_arkit_name(int index);
TH_API const char* th_viseme_name(int index);
TH_API const char* th_vrm_name(int index);
/* The formats' names ("csv", "oculus", "rhubarb-tsv", ...) and their files' extensions (".csv"), NULL past the
 * last. */
TH_API const char* th_format_name(int index);
TH_API const char* th_format_extension(int index);

#ifdef __cplusplus
}
#endif

#endif /* TALKINGHEAD_ABI_FIRST_H */
