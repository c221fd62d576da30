// A character's surface: glTF's metallic-roughness material under the studio lights the face has
// (lighting.glsl), approximated as Lambert diffuse plus a Blinn-Phong lobe whose sharpness follows the
// roughness and whose colour follows the metalness; unlit materials (VRM's MToon, KHR_materials_unlit) show
// their base colour, lifted by the ambient so they sit in the same light. Output premultiplied, sRGB.
// One program per kind of material (the renderer defines these before the source): llvmpipe runs both sides of
// a branch on a uniform, and a shader that may discard tests depth only after shading.
//   ALPHA_MODE  0 opaque, 1 mask (discarded below the cutoff), 2 blend
//   TEXTURED    1: the base colour times its texture
//   UNLIT       1: the base colour alone, lifted by the ambient
//   ROUGH       1: roughness 1 (the specular lobe's least sharpness)
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

#if ROUGH
// specularLight (lighting.glsl) at the least sharpness the shading below gives, shininess 2 (roughness 1): the
// lobe's power a product, where pow() costs llvmpipe a logarithm and an exponential.
vec3 roughSpecularLight(vec3 n, vec3 v, vec3 f0) {
  vec3 sum = vec3(0.0);
  for (int i = 0; i < 3; i += 2) {
    vec3 l = uLightDirection[i];
    vec3 h = normalize(l + v);
    float nl = max(dot(n, l), 0.0);
    float nh = max(dot(n, h), 0.0);
    float lobe = (2.0 + 8.0) / (8.0 * kPi) * (nh * nh);
    sum += uLightColour[i] * (lobe * nl) * (f0 + (1.0 - f0) * schlick(dot(v, h)) * 0.25);
  }
  return sum;
}
#endif

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
#if ROUGH
  vec3 specular = roughSpecularLight(n, v, f0) * (1.0 - 0.7 * uRoughness);
#else
  float shininess = 2.0 / max(uRoughness * uRoughness * uRoughness * uRoughness, 1e-3) - 2.0;
  vec3 specular = specularLight(n, v, clamp(shininess, 2.0, 2048.0), f0) * (1.0 - 0.7 * uRoughness);
#endif
  colour = diffuseColour * (diffuseLight(n, vec3(0.0)) + ambientLight(n)) + specular;
#endif
  colour += uEmissive;
  fragColour = vec4(finish(colour) * alpha, alpha);
}
