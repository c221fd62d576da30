// The GLSL sources of shaders/, embedded at build time (engine/render/embed_shaders.cmake writes
// shader_sources.cpp into the build tree). Internal to the renderer.
// Thread contract: constants.
#pragma once

namespace th::render::shaders {

extern const char* const kFace_vert;
extern const char* const kFace_frag;
extern const char* const kBackground_vert;
extern const char* const kBackground_frag;
extern const char* const kDepth_vert;
extern const char* const kDepth_frag;
extern const char* const kLighting_glsl;
extern const char* const kAvatar_vert;
extern const char* const kAvatar_frag;

}  // namespace th::render::shaders
