// A whole recording from C++: animated offline, summarised, and written in the formats asked for.
//
//   animate speech.wav out.tsv [out.csv ...]      (any recording; each output's extension picks its format)
#include <talkinghead/talkinghead.h>

#include <array>
#include <cstdio>
#include <memory>

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s RECORDING OUTPUT...\n", argv[0]);
    return 2;
  }
  th_models* loaded = nullptr;
  if (th_models_load(nullptr, &loaded) != TH_OK) {  // the installed models
    std::fprintf(stderr, "%s\n", th_last_error());
    return 1;
  }
  const std::unique_ptr<th_models, void (*)(th_models*)> models(loaded, th_models_free);
  th_animation* made = nullptr;
  if (th_animate(models.get(), argv[1], nullptr, &made) != TH_OK) {
    std::fprintf(stderr, "%s\n", th_last_error());
    return 1;
  }
  const std::unique_ptr<th_animation, void (*)(th_animation*)> animation(made, th_animation_free);
  const int frames = th_animation_frames(animation.get());
  // How long each Oculus viseme is shown, and the widest the jaw opens.
  std::array<int, TH_NUM_VISEMES> shown{};
  float widest = 0.0f;
  th_frame frame;
  th_frame_init(&frame);
  for (int i = 0; i < frames; ++i) {
    if (th_animation_frame(animation.get(), i, &frame) != TH_OK) return 1;
    if (frame.viseme >= 0) ++shown[static_cast<std::size_t>(frame.viseme)];
    if (frame.arkit[17] > widest) widest = frame.arkit[17];
  }
  std::printf("%s: %d frames (%.2f s), jawOpen up to %.2f; visemes shown:", argv[1], frames, frames / 30.0, widest);
  for (int v = 0; v < TH_NUM_VISEMES; ++v)
    if (shown[static_cast<std::size_t>(v)] > 0)
      std::printf(" %s %d", th_viseme_name(v), shown[static_cast<std::size_t>(v)]);
  std::printf("\n");
  for (int k = 2; k < argc; ++k) {
    if (th_animation_write(animation.get(), argv[k], nullptr) != TH_OK) {
      std::fprintf(stderr, "%s\n", th_last_error());
      return 1;
    }
    std::printf("wrote %s\n", argv[k]);
  }
  return 0;
}
