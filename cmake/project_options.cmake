# Warnings and sanitizers for project targets only (third-party headers are included as SYSTEM).
add_library(talkinghead_options INTERFACE)
target_compile_options(talkinghead_options INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion -Wnon-virtual-dtor
  -Wold-style-cast -Woverloaded-virtual -Wnull-dereference -Wformat=2
  # GCC 12 reports false -Wrestrict positives inside libstdc++ string code (GCC bug 105329).
  $<$<CXX_COMPILER_ID:GNU>:-Wno-restrict>)
# A program loads only the shared libraries it calls: a test of the HMMs does not start OpenCV, FFmpeg and GL
# (and LeakSanitizer does not scan them at exit), though the engine's stages link them.
target_link_options(talkinghead_options INTERFACE -Wl,--as-needed)
# No code here reads errno after maths calls; without this, std::sqrt blocks vectorisation.
target_compile_options(talkinghead_options INTERFACE -fno-math-errno)
if(TALKINGHEAD_WERROR)
  target_compile_options(talkinghead_options INTERFACE -Werror)
endif()
if(TALKINGHEAD_SANITIZE)
  target_compile_options(talkinghead_options INTERFACE
    -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  target_link_options(talkinghead_options INTERFACE -fsanitize=address,undefined)
  if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    # UBSan stays out of third-party headers (Eigen, Boost, ...): the file says why.
    target_compile_options(talkinghead_options INTERFACE
      -fsanitize-ignorelist=${CMAKE_CURRENT_LIST_DIR}/sanitize_ignorelist.txt)
  endif()
endif()
if(TALKINGHEAD_TSAN)
  target_compile_options(talkinghead_options INTERFACE -fsanitize=thread -fno-omit-frame-pointer)
  target_link_options(talkinghead_options INTERFACE -fsanitize=thread)
endif()

# Precompiled headers: what nearly every file of a target includes (Eigen, the standard library) is parsed once
# per target instead of once per file. Off with -DTALKINGHEAD_PCH=OFF (to check that every file includes what it
# uses). On by default with clang only: GCC 12 reports libstdc++'s code reached through a precompiled header as
# if it were ours (false -Wstringop-overflow and -Warray-bounds on "text" + std::string at -O3).
if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  set(talkinghead_pch_default ON)
else()
  set(talkinghead_pch_default OFF)
endif()
option(TALKINGHEAD_PCH "Precompile the headers most files include" ${talkinghead_pch_default})
function(talkinghead_precompile target)
  if(NOT TALKINGHEAD_PCH)
    return()
  endif()
  target_precompile_headers(${target} PRIVATE <algorithm> <cmath> <filesystem> <memory> <string> <string_view>
                            <vector> <Eigen/Core> ${ARGN})
endfunction()

# talkinghead_diagnostic(target): a program that measures the product for the docs (tools/diagnostics). In the
# sanitized build, where it is compiled but no test runs it, it is compiled without optimisation, in half the time.
function(talkinghead_diagnostic target)
  if(TALKINGHEAD_SANITIZE)
    target_compile_options(${target} PRIVATE -O0)
  endif()
endfunction()
