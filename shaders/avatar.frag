// A character's surface: glTF's metallic-roughness material under the studio lights the face has
// (lighting.glsl), approximated as Lambert diffuse plus a Blinn-Phong lobe whose sharpness follows the
// roughness and whose colour follows the metalness; unlit materials (VRM's MToon, KHR_materials_unlit) show
// their base colour, lifted by the ambient so they sit in the same light. Output premultiplied, sRGB.
in vec3 vPosition;
in vec3 vNormal;
in vec2 vUv;

uniform vec3 uCameraPosition;
uniform vec4 uBaseColour;  // linear RGBA factor
uniform sampler2D uBaseTexture;  // sRGB texture (GL decodes it to linear)
uniform bool uHasTexture;
uniform vec3 uEmissive;
uniform float uMetallic;
uniform float uRoughness;
uniform bool uUnlit;
uniform int uAlphaMode;  // 0 opaque, 1 mask, 2 blend
uniform float uAlphaCutoff;

out vec4 fragColour;

void main() {
  vec4 base = uBaseColour;
  if (uHasTexture) base *= texture(uBaseTexture, vUv);
  if (uAlphaMode == 1 && base.a < uAlphaCutoff) discard;
  float alpha = uAlphaMode == 2 ? base.a : 1.0;
  vec3 n = normalize(vNormal);
  vec3 v = normalize(uCameraPosition - vPosition);
  if (!gl_FrontFacing) n = -n;  // double-sided surfaces lit on the side seen
  vec3 colour;
  if (uUnlit) {
    colour = base.rgb * (0.75 + 0.25 * ambientLight(n) / max(uSkyAmbient, vec3(1e-3)));
  } else {
    vec3 diffuseColour = base.rgb * (1.0 - uMetallic);
    vec3 f0 = mix(vec3(0.04), base.rgb, uMetallic);
    float shininess = 2.0 / max(uRoughness * uRoughness * uRoughness * uRoughness, 1e-3) - 2.0;
    vec3 specular = specularLight(n, v, clamp(shininess, 2.0, 2048.0), f0) * (1.0 - 0.7 * uRoughness);
    colour = diffuseColour * (diffuseLight(n, vec3(0.0)) + ambientLight(n)) + specular;
  }
  colour += uEmissive;
  fragColour = vec4(finish(colour) * alpha, alpha);
}
