// LeakSanitizer suppressions for binaries that render (the render tests and, in sanitizer builds, the
// talkinghead executable itself: link the talkinghead_lsan_suppressions object library). LSan reads this hook
// at start-up, so the suppressions hold however the binary is run (ctest or by hand); without LSan the
// function is never called.
//
// - libOSMesa.so: OSMesaMakeCurrent and OSMesaCreateContextAttribs allocate per-context framebuffer records
//   that Mesa keeps in a process-wide list and never frees (Mesa 22.3, src/gallium/frontends/osmesa), a few
//   hundred bytes per context. Nothing of ours is in those allocations' stacks; Mesa ships without symbols,
//   so the library is the narrowest match there is.
// - The window path (talkinghead show under Xvfb): GLFW and Mesa's GLX/DRI drivers keep per-display and
//   per-context records until exit (libX11's connection caches, the driver's screen). Also stacks with no code
//   of ours and libraries without symbols.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libOSMesa.so\n"
         "leak:libGLX_mesa.so\n"
         "leak:libgallium\n"
         "leak:swrast_dri.so\n"
         "leak:libX11.so\n"
         "leak:libglfw.so\n";
}

// Without this LSan lists the suppressions it used on stderr at exit, which would break the CLI's promise of
// exactly one line of error output.
extern "C" const char* __lsan_default_options() {
  return "print_suppressions=0";
}
