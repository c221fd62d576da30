// A character's surface: glTF's metallic-roughness material under the studio lights the face has
// (lighting.glsl), approximated as Lambert diffuse plus a Blinn-Phong lobe whose sharpness follows the
// roughness and whose colour follows the metalness; unlit materials (VRM's MToon, KHR_materials_unlit) show
// their base colour, lifted by the ambient so they sit in the same light. Output premultiplied, sRGB.
// One program per kind of material (the renderer defines these before the source): llvmpipe runs both sides of
// a branch on a uniform, and a shader that may discard tests depth only after shading.
//   ALPHA_MODE  0 opaque, 1 mask (discarded below the cutoff), 2 blend
//   TEXTURED    1: the base colour times its texture
//   UNLIT       1: the base colour alone, lifted by the ambient
//   DEPTH_ONLY  1: nothing but the alpha test (the depth pass before the shading one)
in vec3 vPosition;
in vec3 vNormal;
in vec2 vUv;

uniform vec3 uCameraPosition;
uniform vec4 uBaseColour;  // linear RGBA factor
uniform sampler2D uBaseTexture;  // sRGB texture (GL decodes it to linear)
uniform vec3 uEmissive;
uniform float uMetallic;
uniform float uRoughness;
uniform float uAlphaCutoff;

out vec4 fragColour;

void main() {
  vec4 base = uBaseColour;
#if TEXTURED
  base *= texture(uBaseTexture, vUv);
#endif
#if ALPHA_MODE == 1
  if (base.a < uAlphaCutoff) discard;
#endif
  float alpha = ALPHA_MODE == 2 ? base.a : 1.0;
#if DEPTH_ONLY
  fragColour = vec4(0.0);  // (colour writes are off)
  return;
#endif
  vec3 n = normalize(vNormal);
  if (!gl_FrontFacing) n = -n;  // double-sided surfaces lit on the side seen
  vec3 colour;
#if UNLIT
  colour = base.rgb * (0.75 + 0.25 * ambientLight(n) / max(uSkyAmbient, vec3(1e-3)));
#else
  vec3 v = normalize(uCameraPosition - vPosition);
  vec3 diffuseColour = base.rgb * (1.0 - uMetallic);
  vec3 f0 = mix(vec3(0.04), base.rgb, uMetallic);
  float shininess = 2.0 / max(uRoughness * uRoughness * uRoughness * uRoughness, 1e-3) - 2.0;
  vec3 specular = specularLight(n, v, clamp(shininess, 2.0, 2048.0), f0) * (1.0 - 0.7 * uRoughness);
  colour = diffuseColour * (diffuseLight(n, vec3(0.0)) + ambientLight(n)) + specular;
#endif
  colour += uEmissive;
  fragColour = vec4(finish(colour) * alpha, alpha);
}
