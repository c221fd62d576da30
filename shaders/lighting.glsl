// Shared by the face's vertex and fragment shaders (the renderer puts it after the #version and #define lines
// of both): the studio lights and the lighting model.
uniform vec3 uLightDirection[3];  // towards the key, fill and rim lights, world space, unit length
uniform vec3 uLightColour[3];     // linear
uniform vec3 uSkyAmbient;         // linear, light from above
uniform vec3 uGroundAmbient;      // linear, light from below
uniform float uExposure;

const float kPi = 3.14159265;

vec3 ambientLight(vec3 n) { return mix(uGroundAmbient, uSkyAmbient, 0.5 + 0.5 * n.y); }

float schlick(float cosine) {
  float m = 1.0 - max(cosine, 0.0);
  float m2 = m * m;
  return m2 * m2 * m;
}

// Diffuse light from the three lights, wrapped past the terminator by `wrap` (per colour channel: red light
// scatters furthest under skin, a cheap stand-in for subsurface scattering); energy-preserving.
vec3 diffuseLight(vec3 n, vec3 wrap) {
  vec3 sum = vec3(0.0);
  for (int i = 0; i < 3; ++i) {
    float nl = dot(n, uLightDirection[i]);
    sum += uLightColour[i] * clamp((nl + wrap) / ((1.0 + wrap) * (1.0 + wrap)), 0.0, 1.0);
  }
  return sum;
}

// Normalised Blinn-Phong with Schlick's Fresnel, from the key and the rim light (the fill is soft: no
// highlight).
vec3 specularLight(vec3 n, vec3 v, float shininess, vec3 f0) {
  vec3 sum = vec3(0.0);
  for (int i = 0; i < 3; i += 2) {
    vec3 l = uLightDirection[i];
    vec3 h = normalize(l + v);
    float nl = max(dot(n, l), 0.0);
    float lobe = (shininess + 8.0) / (8.0 * kPi) * pow(max(dot(n, h), 0.0), shininess);
    sum += uLightColour[i] * (lobe * nl) * (f0 + (1.0 - f0) * schlick(dot(v, h)) * 0.25);
  }
  return sum;
}

// Per-vertex ambient openness through a curve that leaves the face's gentle hollows (above ~0.85) lit and
// sinks crevices (nostrils, the mouth's corners) towards black: without shadows, direct light would brighten
// them.
float openness(float measured) { return smoothstep(0.1, 0.85, measured); }

// Ambient light is occluded fully; direct light mostly.
float directOcclusion(float open) { return mix(1.0, open, 0.85); }

// sRGB encoding from square roots (cheap in SIMD), within 0.3 % of the exact curve above 0.0031308.
vec3 toSrgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  vec3 s1 = sqrt(c);
  vec3 s2 = sqrt(s1);
  vec3 s3 = sqrt(s2);
  vec3 curve = 0.585122381 * s1 + 0.783140355 * s2 - 0.368262736 * s3;
  return mix(12.92 * c, curve, step(vec3(0.0031308), c));
}

// Identity up to the knee, then a soft shoulder towards 1: highlights roll off instead of clipping flat.
vec3 shoulder(vec3 c) {
  const float knee = 0.8;
  vec3 over = max(c - knee, 0.0);
  return min(c, vec3(knee)) + over * (1.0 - knee) / (over + (1.0 - knee));
}

vec3 finish(vec3 linear) { return toSrgb(shoulder(linear * uExposure)); }

// A pseudo-random value in 0..1 per point, for detail drawn from texture coordinates; from arithmetic alone
// (no sine: cheaper in SIMD).
float hash(vec2 p) {
  vec3 q = fract(vec3(p.xyx) * 0.1031);
  q += dot(q, q.yzx + 33.33);
  return fract((q.x + q.y) * q.z);
}

