/* talkinghead: speech in, a talking face's animation out, on a CPU, live or from a file.
 *
 * The C API of libtalkinghead (semantic versioning: TALKINGHEAD_VERSION_*, from talkinghead/version.h). Every
 * function that can fail returns a th_status; th_last_error() says what went wrong, in one line, on the calling
 * thread.
 *
 * Growing without breaking: a struct the caller allocates (th_models_options, th_stream_settings,
 * th_animate_options, th_export_options, th_frame) starts with struct_size, the size the caller was compiled with,
 * set by its _init call. A minor version only appends fields to these structs. The library reads and writes only
 * the bytes struct_size covers and gives the fields past them their defaults, so a program compiled against an
 * older header of the same major version runs against a newer library; a struct_size smaller than the struct's
 * first version is refused (TH_ERROR_ARGUMENT). Other structs are opaque. While the major version is 0 a minor
 * version may still break: 0.2 put struct_size at the start of th_stream_options and th_frame, so programs built
 * against 0.1 must be rebuilt. Each verb takes its own options (NULL for the defaults): the models, a stream, a
 * file animated, an export; the calls before them, on one th_stream_options for all, are deprecated.
 *
 *   th_models* models = NULL;                         // the model files read once, for many streams and files
 *   if (th_models_load(NULL, &models) != TH_OK)       // NULL: the installed models, the head's own motion
 *     fprintf(stderr, "%s\n", th_last_error());
 *
 *   th_stream_settings settings;
 *   th_stream_settings_init(&settings);               // 16 kHz
 *   settings.sample_rate_hz = 48000;
 *   th_stream* stream = NULL;
 *   th_stream_start(models, &settings, &stream);      // as many as wanted, on any threads
 *   th_stream_push(stream, samples, count);           // mono float samples, any block size
 *   th_frame frame;
 *   th_frame_init(&frame);                            // its struct_size
 *   while (th_stream_pull(stream, &frame) == 1) use(&frame);   // 30 frames a second, in order
 *   th_stream_finish(stream);                         // the input has ended: the last frames
 *   th_stream_close(stream);
 *
 *   th_animation* animation = NULL;                   // a whole recording
 *   th_animate(models, "speech.wav", NULL, &animation);
 *   th_animation_write(animation, "speech.tsv", NULL);   // any animate format: by extension, or named
 *   th_animation_free(animation);
 *
 *   th_export_options video;                          // the face speaking it, as MP4
 *   th_export_options_init(&video);                   // 1280x720, 30 fps, our face, the installed models
 *   video.models = models;
 *   video.progress = show;                            // int show(double done, void* user_data): non-zero stops
 *   th_export("speech.wav", "speech.mp4", &video);    // TH_ERROR_CANCELLED, and no file, if show said stop
 *   th_models_free(models);                           // the streams keep what they use
 *
 *   th_models_options choice;                         // other models, or the head moving like a person
 *   th_models_options_init(&choice);
 *   choice.head_style = "me.json";
 *   th_models_load(&choice, &models);
 *
 * A frame: its time, the MPEG-4 FAPs (the face's standard parameters), ARKit's 52 blendshape weights, the
 * Oculus/OpenXR 15 viseme weights and VRM's five vowels, the viseme shown (held at least 67 ms; 100 ms from a
 * viseme model) and Rhubarb's mouth shape for it, and the head's rotation.
 *
 * Threads: a stream or an animation belongs to one thread at a time; different ones may be used on different
 * threads at once. A th_models handle may be used by any number of threads at once. Progress callbacks are called
 * on the thread that called the function they were given to. The library starts no threads of its own, but for an
 * export's encoder, which it joins before returning. */
#ifndef TALKINGHEAD_TALKINGHEAD_H
#define TALKINGHEAD_TALKINGHEAD_H

#include <stddef.h>

#include "talkinghead/version.h" /* TALKINGHEAD_VERSION_MAJOR, _MINOR, _PATCH and TALKINGHEAD_VERSION ("0.3.0") */

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__)
#define TH_API __attribute__((visibility("default")))
#define TH_DEPRECATED(replacement) __attribute__((deprecated("use " replacement)))
#else
#define TH_API
#define TH_DEPRECATED(replacement)
#endif

typedef enum th_status {
  TH_OK = 0,
  TH_ERROR_ARGUMENT = 1, /* a null pointer, a rate or option out of range */
  TH_ERROR_FILE = 2,     /* a file that cannot be read or written, or is not what it should be */
  TH_ERROR_STATE = 3,    /* a call out of order: pushing after th_stream_finish */
  TH_ERROR_INTERNAL = 4, /* anything else (out of memory) */
  TH_ERROR_CANCELLED = 5 /* a progress callback asked to stop: no output was made */
} th_status;

/* "0.3.0": the library's version (compare with the TALKINGHEAD_VERSION_* it was compiled against). */
TH_API const char* th_version(void);
/* The message of the last failure on this thread ("" if none); valid until the next call that fails. */
TH_API const char* th_last_error(void);

enum {
  TH_NUM_FAPS = 68,    /* FAPs 1..68: th_frame.faps[n] is FAP n (faps[0] unused) */
  TH_NUM_ARKIT = 52,   /* th_arkit_name(i) */
  TH_NUM_VISEMES = 15, /* th_viseme_name(i): sil PP FF TH DD kk CH SS nn RR aa E ih oh ou */
  TH_NUM_VRM = 5       /* th_vrm_name(i): A I U E O */
};

/* Its first version ends at head_roll_deg; the fields after it were appended (a program built before them gets
 * frames without them). */
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
  float head_rotation_unity[4];  /* the same rotation as a quaternion x, y, z, w in Unity's left-handed frame
                                    (x to the avatar's right), as VMC sends it */
} th_frame;

/* The _init calls are macros that pass the struct's size as the caller was compiled: the library fills only that
 * much (each returns TH_ERROR_ARGUMENT for NULL or a size below the struct's first version). */
#define th_frame_init(frame) th_frame_init_sized((frame), sizeof(th_frame))
TH_API th_status th_frame_init_sized(th_frame* frame, size_t struct_size);

/* Called by file work (th_animate, th_export) with the fraction done, 0..1, on the calling thread; a non-zero
 * return stops the work, which then fails with TH_ERROR_CANCELLED and leaves no output. */
typedef int (*th_progress_fn)(double fraction_done, void* user_data);

/* Which models to read, and how the head moves. */
typedef struct th_models_options {
  size_t struct_size;       /* sizeof(th_models_options) as the caller was compiled: th_models_options_init */
  const char* head_model;   /* a model file; NULL: the installed one; "": no head motion */
  const char* mouth_model;  /* a model file for streams and files alike; NULL: the installed ones (live's for
                               streams, the offline path's for files); "": no mouth */
  const char* viseme_model; /* NULL: the installed articulation's visemes (lips closed by the same classes);
                               a file: that viseme model's, without the articulation; "": no visemes */
  const char* head_style;   /* the head moves like a person: a style file (`talkinghead style` makes one from a
                               talking video) or a head-pose CSV (time_s, pitch_deg, yaw_deg, roll_deg) with the
                               WAV of its name beside it; NULL: the model's own motion. Read with the models, and
                               kept for their streams, animations and exports */
} th_models_options;

/* The defaults: the installed models, the head model's own motion. */
#define th_models_options_init(options) th_models_options_init_sized((options), sizeof(th_models_options))
TH_API th_status th_models_options_init_sized(th_models_options* options, size_t struct_size);

/* The models, read once and shared: by any number of streams and files, on any threads at once. options NULL:
 * the defaults. The stream models and the head style are read now (a bad file fails here, TH_ERROR_FILE naming
 * it); the file models (th_animate, th_export) on first use. Freeing the handle does not end the streams started
 * on it: each keeps the models it uses. */
typedef struct th_models th_models;
TH_API th_status th_models_load(const th_models_options* options, th_models** models);
TH_API void th_models_free(th_models* models);

typedef struct th_stream th_stream;

/* How a stream takes its samples and gives its frames. */
typedef struct th_stream_settings {
  size_t struct_size;    /* sizeof(th_stream_settings) as the caller was compiled: th_stream_settings_init */
  double sample_rate_hz; /* of the pushed samples, 8000..192000 (default 16000) */
  int wait_for_head;     /* 0: frames as soon as the mouth is decided (the head shown its own look-ahead late);
                            1: each frame waits for its own head (th_stream_latency_ms says how long) */
} th_stream_settings;

/* The defaults: 16000 Hz, frames not waiting for the head. */
#define th_stream_settings_init(settings) th_stream_settings_init_sized((settings), sizeof(th_stream_settings))
TH_API th_status th_stream_settings_init_sized(th_stream_settings* settings, size_t struct_size);

/* A live stream on loaded models (NULL: the installed ones, read for this stream alone); settings NULL: the
 * defaults. */
TH_API th_status th_stream_start(const th_models* models, const th_stream_settings* settings, th_stream** stream);
TH_API th_status th_stream_push(th_stream* stream, const float* samples, size_t count);
TH_API th_status th_stream_finish(th_stream* stream);
/* 1: a frame was written to *frame; 0: none is ready yet (push more, or finish); -1: an error. */
TH_API int th_stream_pull(th_stream* stream, th_frame* frame);
/* How far past a frame's instant the input must reach before the frame is out, ms. */
TH_API double th_stream_latency_ms(const th_stream* stream);
TH_API void th_stream_close(th_stream* stream);

typedef struct th_animation th_animation;

/* How a whole recording is animated. */
typedef struct th_animate_options {
  size_t struct_size;      /* sizeof(th_animate_options) as the caller was compiled: th_animate_options_init */
  th_progress_fn progress; /* called when the work starts and when it ends (the offline animation is one step);
                              NULL: not */
  void* user_data;         /* handed to progress */
} th_animate_options;

/* The defaults: no progress callback. */
#define th_animate_options_init(options) th_animate_options_init_sized((options), sizeof(th_animate_options))
TH_API th_status th_animate_options_init_sized(th_animate_options* options, size_t struct_size);

/* A whole recording (WAV, FLAC, OGG, MP3, or a video's sound) animated offline on loaded models (their file
 * models, read on first use; NULL: the installed ones, read for this recording alone): the best the models do,
 * with the whole recording to look at. options NULL: the defaults. */
TH_API th_status th_animate(const th_models* models, const char* recording, const th_animate_options* options,
                            th_animation** animation);
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
typedef struct th_export_options {
  size_t struct_size;       /* sizeof(th_export_options) as the caller was compiled: th_export_options_init */
  int width;                /* even, 16..7680 (default 1280) */
  int height;               /* even, 16..4320 (default 720) */
  double frames_per_second; /* 1..120 (default 30) */
  int crf;                  /* H.264 quality, 0..51, lower is better and larger (default 20) */
  const char* avatar;       /* a character instead of our face: a .glb, .gltf or .vrm file whose ARKit, Oculus viseme
                               or VRM morph targets and neck, head and eye bones the speech moves, as `talkinghead
                               export --avatar` takes it (NULL: ours); one that cannot be read, or has nothing the
                               speech can move, fails with TH_ERROR_FILE naming it, and no video is written */
  const th_models* models;  /* the models to animate with (NULL: the installed ones, read for this export) */
  th_progress_fn progress;  /* called before each frame is rendered, with the share encoded, and once (at 1)
                               when the file is written, which no longer cancels (NULL: not) */
  void* user_data;          /* handed to progress */
} th_export_options;

#define th_export_options_init(options) th_export_options_init_sized((options), sizeof(th_export_options))
TH_API th_status th_export_options_init_sized(th_export_options* options, size_t struct_size);
TH_API th_status th_export(const char* recording, const char* mp4, const th_export_options* options);

TH_API const char* th_arkit_name(int index);
TH_API const char* th_viseme_name(int index);
TH_API const char* th_vrm_name(int index);
/* The formats' names ("csv", "oculus", "rhubarb-tsv", ...) and their files' extensions (".csv"), NULL past the
 * last. */
TH_API const char* th_format_name(int index);
TH_API const char* th_format_extension(int index);

/* Deprecated, kept and working for programs built against 0.2: the calls from before each verb had options of its
 * own, when th_stream_options served them all and each call ignored part of it. */

/* Its first version ends at wait_for_head; the fields after it were appended (a program built before them has no
 * progress callback and no head style). */
typedef struct th_stream_options {
  size_t struct_size;       /* sizeof(th_stream_options) as the caller was compiled: th_stream_options_init */
  const char* head_model;   /* as th_models_options' */
  const char* mouth_model;  /* as th_models_options' */
  const char* viseme_model; /* as th_models_options' */
  double sample_rate_hz;    /* as th_stream_settings' */
  int wait_for_head;        /* as th_stream_settings' */
  th_progress_fn progress;  /* as th_animate_options' */
  void* user_data;          /* handed to progress */
  const char* head_style;   /* as th_models_options' */
} th_stream_options;

/* The defaults: the installed models, 16000 Hz, frames not waiting for the head, no callback. */
#define th_stream_options_init(options) th_stream_options_init_sized((options), sizeof(th_stream_options))
TH_API TH_DEPRECATED("th_models_options_init, th_stream_settings_init or th_animate_options_init") th_status
    th_stream_options_init_sized(th_stream_options* options, size_t struct_size);
/* th_models_load with options' model files and head style. */
TH_API TH_DEPRECATED("th_models_load with th_models_options") th_status
    th_models_open(const th_stream_options* options, th_models** models);
/* A stream on models of its own: th_models_load, then th_stream_start. */
TH_API TH_DEPRECATED("th_models_load, then th_stream_start with th_stream_settings") th_status
    th_stream_open(const th_stream_options* options, th_stream** stream);
/* th_stream_start with options' rate and wait_for_head (its model files are not used). */
TH_API TH_DEPRECATED("th_stream_start with th_stream_settings") th_status
    th_stream_open_models(const th_models* models, const th_stream_options* options, th_stream** stream);
/* th_animate on file models of its own (the stream models are not read). */
TH_API TH_DEPRECATED("th_models_load, then th_animate with th_animate_options") th_status
    th_animate_file(const char* recording, const th_stream_options* options, th_animation** animation);
/* th_animate with options' progress callback (the rest is not used). */
TH_API TH_DEPRECATED("th_animate with th_animate_options") th_status
    th_animate_file_models(const th_models* models, const char* recording, const th_stream_options* options,
                           th_animation** animation);
/* th_export with the default options but the size (th_export_options' width and height), and the character (its
 * avatar). */
TH_API TH_DEPRECATED("th_export with th_export_options' width and height") th_status
    th_export_file(const char* recording, const char* mp4, int width, int height);
TH_API TH_DEPRECATED("th_export with th_export_options' width, height and avatar") th_status
    th_export_file_avatar(const char* recording, const char* mp4, int width, int height, const char* avatar);

#ifdef __cplusplus
}
#endif

#endif /* TALKINGHEAD_TALKINGHEAD_H */
