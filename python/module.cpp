// The Python module `talkinghead` (pybind11) over libtalkinghead's C API: numpy arrays in and out.
//
//   import talkinghead, numpy
//   stream = talkinghead.Stream(sample_rate=48000)
//   stream.push(samples)                        # float32 mono, any length
//   frames = stream.pull()                      # the frames ready: a dict of arrays, one row per frame
//   animation = talkinghead.animate("speech.wav")
//   animation.arrays()["arkit"]                 # (frames, 52)
//   animation.write("speech.tsv")               # any format animate writes
//   animation.write_avatar("talk.glb", "me.vrm")   # the character with the speech as its glTF animation
//   models = talkinghead.Models()               # read once: Stream(models=models), animate(..., models=models)
//   talkinghead.export("speech.wav", "talk.mp4", progress=print)   # called with the fraction done; True cancels
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "talkinghead/talkinghead.h"

namespace py = pybind11;

namespace {

struct TalkingheadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// A progress callback asked to stop (returned true).
struct CancelledError : TalkingheadError {
  using TalkingheadError::TalkingheadError;
};

void check(th_status status) {
  if (status == TH_ERROR_CANCELLED) throw CancelledError(th_last_error());
  if (status != TH_OK) throw TalkingheadError(th_last_error());
}

// A Python callable as the C API's progress callback, called on the thread that released the GIL: a true result
// cancels; an exception it raises cancels too and is raised again once the work has stopped.
class Progress {
 public:
  explicit Progress(std::optional<py::function> callable) : callable_(std::move(callable)) {}
  th_progress_fn function() const { return callable_ ? &Progress::call : nullptr; }
  void* userData() { return this; }
  // After the C call, with the GIL held: the callable's exception, if it raised one.
  void check(th_status status) {
    if (error_) throw std::move(*error_);
    ::check(status);
  }

 private:
  static int call(double fraction, void* userData) {
    auto* self = static_cast<Progress*>(userData);
    const py::gil_scoped_acquire locked;
    try {
      return py::bool_((*self->callable_)(fraction)) ? 1 : 0;
    } catch (py::error_already_set& error) {
      self->error_ = std::move(error);
      return 1;
    }
  }
  std::optional<py::function> callable_;
  std::optional<py::error_already_set> error_;
};

struct ModelChoice {
  std::optional<std::string> head, mouth, visemes, headStyle;
  bool any() const { return head || mouth || visemes || headStyle; }
  // NULL for the installed model, the path otherwise ("" switches the part off).
  th_models_options options() const {
    th_models_options o;
    check(th_models_options_init(&o));
    o.head_model = head ? head->c_str() : nullptr;
    o.mouth_model = mouth ? mouth->c_str() : nullptr;
    o.viseme_model = visemes ? visemes->c_str() : nullptr;
    o.head_style = headStyle ? headStyle->c_str() : nullptr;
    return o;
  }
};

// Frames as a dict of arrays, one row per frame.
py::dict arraysOf(const std::vector<th_frame>& frames) {
  const auto n = static_cast<py::ssize_t>(frames.size());
  py::array_t<int> index(n), viseme(n);
  py::array_t<double> time(n);
  py::array_t<float> faps({n, py::ssize_t{TH_NUM_FAPS + 1}}), arkit({n, py::ssize_t{TH_NUM_ARKIT}}),
      visemes({n, py::ssize_t{TH_NUM_VISEMES}}), vrm({n, py::ssize_t{TH_NUM_VRM}}), head({n, py::ssize_t{3}}),
      headUnity({n, py::ssize_t{4}});
  std::string shapes;
  auto f = faps.mutable_unchecked<2>();
  auto a = arkit.mutable_unchecked<2>();
  auto v = visemes.mutable_unchecked<2>();
  auto r = vrm.mutable_unchecked<2>();
  auto h = head.mutable_unchecked<2>();
  auto u = headUnity.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < n; ++i) {
    const th_frame& frame = frames[static_cast<std::size_t>(i)];
    index.mutable_at(i) = frame.index;
    time.mutable_at(i) = frame.time_seconds;
    viseme.mutable_at(i) = frame.viseme;
    shapes += frame.rhubarb_shape;
    for (int k = 0; k <= TH_NUM_FAPS; ++k) f(i, k) = frame.faps[k];
    for (int k = 0; k < TH_NUM_ARKIT; ++k) a(i, k) = frame.arkit[k];
    for (int k = 0; k < TH_NUM_VISEMES; ++k) v(i, k) = frame.visemes[k];
    for (int k = 0; k < TH_NUM_VRM; ++k) r(i, k) = frame.vrm[k];
    h(i, 0) = frame.head_pitch_deg;
    h(i, 1) = frame.head_yaw_deg;
    h(i, 2) = frame.head_roll_deg;
    for (int k = 0; k < 4; ++k) u(i, k) = frame.head_rotation_unity[k];
  }
  py::dict out;
  out["index"] = index;
  out["time"] = time;
  out["faps"] = faps;
  out["arkit"] = arkit;
  out["visemes"] = visemes;
  out["vrm"] = vrm;
  out["viseme"] = viseme;
  out["rhubarb"] = shapes;
  out["head"] = head;
  out["head_unity"] = headUnity;  // x, y, z, w
  return out;
}

// One frame as a dict: the same keys as arraysOf's, each its row (numbers for the scalars).
py::dict frameOf(const th_frame& frame) {
  py::dict out;
  out["index"] = frame.index;
  out["time"] = frame.time_seconds;
  out["faps"] = py::array_t<float>(TH_NUM_FAPS + 1, frame.faps);
  out["arkit"] = py::array_t<float>(TH_NUM_ARKIT, frame.arkit);
  out["visemes"] = py::array_t<float>(TH_NUM_VISEMES, frame.visemes);
  out["vrm"] = py::array_t<float>(TH_NUM_VRM, frame.vrm);
  out["viseme"] = frame.viseme;
  out["rhubarb"] = std::string(1, frame.rhubarb_shape);
  const std::array<double, 3> head{frame.head_pitch_deg, frame.head_yaw_deg, frame.head_roll_deg};
  out["head"] = py::array_t<double>(3, head.data());
  out["head_unity"] = py::array_t<float>(4, frame.head_rotation_unity);
  return out;
}

// The models read once (th_models): streams, animations and exports on it share them.
class Models {
 public:
  explicit Models(const ModelChoice& choice) {
    const th_models_options options = choice.options();
    th_models* loaded = nullptr;
    {
      py::gil_scoped_release unlocked;
      check(th_models_load(&options, &loaded));
    }
    models_.reset(loaded, th_models_free);
  }
  const th_models* get() const { return models_.get(); }

 private:
  std::shared_ptr<th_models> models_;
};

// The models given, or those the choice names, read into `own` for the one call that needs them; NULL for the
// installed ones, which the library reads for the call (an animation only the file models it uses).
const th_models* modelsFor(const Models* given, const ModelChoice& choice, std::optional<Models>& own) {
  if (given != nullptr) return given->get();
  if (!choice.any()) return nullptr;
  own.emplace(choice);
  return own->get();
}

class Stream {
 public:
  // On `models` (not null), or on models of its own, read from the files `choice` names.
  Stream(double sampleRate, const ModelChoice& choice, bool waitForHead, const Models* models) {
    th_stream_settings settings;
    check(th_stream_settings_init(&settings));
    settings.sample_rate_hz = sampleRate;
    settings.wait_for_head = waitForHead ? 1 : 0;
    std::optional<Models> own;  // the stream keeps what it uses
    check(th_stream_start(modelsFor(models, choice, own), &settings, &stream_));
  }
  ~Stream() { th_stream_close(stream_); }
  Stream(const Stream&) = delete;
  Stream& operator=(const Stream&) = delete;

  void push(const py::array_t<float, py::array::c_style | py::array::forcecast>& samples) {
    if (samples.ndim() != 1) throw TalkingheadError("Stream.push: samples must be one-dimensional (mono)");
    open();
    check(th_stream_push(stream_, samples.data(), static_cast<std::size_t>(samples.size())));
  }
  void finish() {
    open();
    check(th_stream_finish(stream_));
  }
  py::dict pull() {
    open();
    std::vector<th_frame> frames;
    th_frame frame;
    check(th_frame_init(&frame));
    int got = 0;
    while ((got = th_stream_pull(stream_, &frame)) == 1) frames.push_back(frame);
    if (got < 0) throw TalkingheadError(th_last_error());
    return arraysOf(frames);
  }
  double latencyMs() const { return th_stream_latency_ms(stream_); }
  void close() {
    th_stream_close(stream_);
    stream_ = nullptr;
  }

 private:
  void open() const {
    if (stream_ == nullptr) throw TalkingheadError("the stream is closed");
  }
  th_stream* stream_ = nullptr;
};

class Animation {
 public:
  explicit Animation(th_animation* animation) : animation_(animation) {}
  ~Animation() { th_animation_free(animation_); }
  Animation(const Animation&) = delete;
  Animation& operator=(const Animation&) = delete;

  int frames() const { return th_animation_frames(animation_); }
  py::dict arrays() const {
    th_frame empty;
    check(th_frame_init(&empty));
    std::vector<th_frame> all(static_cast<std::size_t>(frames()), empty);
    for (int i = 0; i < frames(); ++i) check(th_animation_frame(animation_, i, &all[static_cast<std::size_t>(i)]));
    return arraysOf(all);
  }
  // Frame i (negative: from the end, as a list); IndexError past either end, which also ends iteration.
  py::dict frame(int i) const {
    const int n = frames();
    if (i < 0) i += n;
    if (i < 0 || i >= n) throw py::index_error("frame " + std::to_string(i) + " of " + std::to_string(n));
    th_frame one;
    check(th_frame_init(&one));
    check(th_animation_frame(animation_, i, &one));
    return frameOf(one);
  }
  void write(const std::string& path, const std::optional<std::string>& format) const {
    check(th_animation_write(animation_, path.c_str(), format ? format->c_str() : nullptr));
  }
  void writeAvatar(const std::string& path, const std::string& avatar, bool animationOnly) const {
    py::gil_scoped_release unlocked;  // reading the character and writing it take a while
    check(th_animation_write_avatar(animation_, avatar.c_str(), path.c_str(), animationOnly ? 1 : 0));
  }

 private:
  th_animation* animation_;
};

std::vector<std::string> namesOf(const char* (*name)(int)) {
  std::vector<std::string> names;
  for (int i = 0; name(i) != nullptr; ++i) names.emplace_back(name(i));
  return names;
}

// The classes: Models, Stream, Animation.
void bindClasses(py::module_& module) {
  py::class_<Models>(module, "Models",
                     "The models read once, for many streams, animations and exports (on any threads)")
      .def(py::init([](std::optional<std::string> head, std::optional<std::string> mouth,
                       std::optional<std::string> visemes, std::optional<std::string> headStyle) {
             return std::make_unique<Models>(ModelChoice{head, mouth, visemes, headStyle});
           }),
           py::arg("head_model") = py::none(), py::arg("mouth_model") = py::none(),
           py::arg("viseme_model") = py::none(), py::arg("head_style") = py::none());

  py::class_<Stream>(module, "Stream", "Speech in as it comes, animation frames out (30 a second)")
      .def(py::init([](double sampleRate, std::optional<std::string> head, std::optional<std::string> mouth,
                       std::optional<std::string> visemes, bool waitForHead, const Models* models,
                       std::optional<std::string> headStyle) {
             const ModelChoice choice{head, mouth, visemes, headStyle};
             if (models != nullptr && choice.any())
               throw TalkingheadError("Stream: models, or the model files and head style, not both");
             return std::make_unique<Stream>(sampleRate, choice, waitForHead, models);
           }),
           py::arg("sample_rate") = 16000.0, py::arg("head_model") = py::none(), py::arg("mouth_model") = py::none(),
           py::arg("viseme_model") = py::none(), py::arg("wait_for_head") = false, py::arg("models") = py::none(),
           py::arg("head_style") = py::none())
      .def("push", &Stream::push, py::arg("samples"), "Mono samples (float32; other dtypes are converted)")
      .def("finish", &Stream::finish, "The input has ended: the last frames become ready")
      .def("pull", &Stream::pull, "The frames ready: a dict of arrays (index, time, faps, arkit, visemes, vrm, ...)")
      .def_property_readonly("latency_ms", &Stream::latencyMs)
      .def("close", &Stream::close)
      .def("__enter__", [](Stream& stream) -> Stream& { return stream; })
      .def("__exit__", [](Stream& stream, py::args) { stream.close(); });

  py::class_<Animation>(module, "Animation", "A whole recording's animation")
      .def_property_readonly("frames", &Animation::frames)
      .def("arrays", &Animation::arrays, "A dict of arrays, one row per frame")
      .def("__len__", &Animation::frames)
      .def("__getitem__", &Animation::frame, py::arg("index"), "Frame `index` as a dict (the keys of arrays())")
      .def(
          "__iter__",
          [](py::object self) {
            const py::module_ builtins = py::module_::import("builtins");
            return builtins.attr("iter")(
                builtins.attr("map")(self.attr("__getitem__"), builtins.attr("range")(py::len(self))));
          },
          "The frames in order, each a dict")
      .def("write", &Animation::write, py::arg("path"), py::arg("format") = py::none(),
           "Write it in any format animate writes (by the extension, or named)")
      .def("write_avatar", &Animation::writeAvatar, py::arg("path"), py::arg("avatar"),
           py::arg("animation_only") = false,
           "Write a character (.glb, .gltf, .vrm) with this speech as its glTF animation to path (.glb, .gltf, "
           ".vrm); animation_only: the animation alone, with the character's nodes and morph target names");
}

// The functions: animate, export, and the formats' names.
void bindFunctions(py::module_& module) {
  module.def(
      "animate",
      [](const std::string& path, std::optional<std::string> head, std::optional<std::string> mouth,
         std::optional<std::string> visemes, const Models* models, std::optional<py::function> callable,
         std::optional<std::string> headStyle) {
        const ModelChoice choice{head, mouth, visemes, headStyle};
        if (models != nullptr && choice.any())
          throw TalkingheadError("animate: models, or the model files and head style, not both");
        std::optional<Models> own;
        const th_models* animateWith = modelsFor(models, choice, own);
        th_animate_options options;
        check(th_animate_options_init(&options));
        Progress progress(std::move(callable));
        options.progress = progress.function();
        options.user_data = progress.userData();
        th_animation* animation = nullptr;
        th_status status = TH_OK;
        {
          py::gil_scoped_release unlocked;  // the work is ours: other Python threads go on
          status = th_animate(animateWith, path.c_str(), &options, &animation);
        }
        progress.check(status);
        return std::make_unique<Animation>(animation);
      },
      py::arg("path"), py::arg("head_model") = py::none(), py::arg("mouth_model") = py::none(),
      py::arg("viseme_model") = py::none(), py::arg("models") = py::none(), py::arg("progress") = py::none(),
      py::arg("head_style") = py::none(),
      "A recording animated offline; progress(fraction) is called at the start and the end, and a true result "
      "cancels (talkinghead.Cancelled)");
  module.def(
      "export",
      [](const std::string& recording, const std::string& mp4, int width, int height, std::optional<std::string> avatar,
         double fps, int crf, const Models* models, std::optional<py::function> callable) {
        th_export_options options;
        check(th_export_options_init(&options));
        options.width = width;
        options.height = height;
        options.frames_per_second = fps;
        options.crf = crf;
        options.avatar = avatar ? avatar->c_str() : nullptr;
        options.models = models != nullptr ? models->get() : nullptr;
        Progress progress(std::move(callable));
        options.progress = progress.function();
        options.user_data = progress.userData();
        th_status status = TH_OK;
        {
          py::gil_scoped_release unlocked;
          status = th_export(recording.c_str(), mp4.c_str(), &options);
        }
        progress.check(status);
      },
      py::arg("recording"), py::arg("mp4"), py::arg("width") = 1280, py::arg("height") = 720,
      py::arg("avatar") = py::none(), py::arg("fps") = 30.0, py::arg("crf") = 20, py::arg("models") = py::none(),
      py::arg("progress") = py::none(),
      "The face speaking a recording, rendered off-screen to MP4; avatar: a character (.glb, .gltf, .vrm) "
      "instead. progress(fraction) is called as frames are encoded: a true result cancels "
      "(talkinghead.Cancelled), an exception it raises cancels and is raised; either leaves no file");
  module.def(
      "formats", [] { return namesOf(th_format_name); }, "The animation formats' names");
  module.def(
      "format_extension",
      [](const std::string& name) {
        for (int i = 0; th_format_name(i) != nullptr; ++i)
          if (name == th_format_name(i)) return std::string(th_format_extension(i));
        throw TalkingheadError("no animation format \"" + name + "\"");
      },
      py::arg("name"));
}

}  // namespace

PYBIND11_MODULE(_talkinghead, module) {
  module.doc() = "talkinghead: speech in, a talking face's animation out (libtalkinghead's Python binding)";
  const auto error = py::register_exception<TalkingheadError>(module, "Error", PyExc_RuntimeError);
  py::register_exception<CancelledError>(module, "Cancelled", error.ptr());
  module.attr("__version__") = TALKINGHEAD_VERSION;  // the header's; th_version() is the library's

  bindClasses(module);
  bindFunctions(module);
  module.attr("arkit_names") = namesOf(th_arkit_name);
  module.attr("viseme_names") = namesOf(th_viseme_name);
  module.attr("vrm_names") = namesOf(th_vrm_name);
}
