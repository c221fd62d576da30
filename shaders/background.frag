#version 330 core
// A studio backdrop: a vertical gradient (colours in sRGB) with a soft pool of light behind the head and
// darker corners, so the head stands out without a hard edge. Polynomial falloff: no transcendental per
// pixel.
in vec2 vUv;
out vec4 fragColour;

uniform vec3 uTop;      // sRGB
uniform vec3 uBottom;   // sRGB
uniform float uAspect;  // width / height

void main() {
  vec3 colour = mix(uBottom, uTop, smoothstep(0.0, 1.0, vUv.y));
  vec2 centred = (vUv - vec2(0.5, 0.6)) * vec2(uAspect, 1.0);
  float pool = clamp(1.0 - dot(centred, centred) * 1.1, 0.0, 1.0);
  colour *= 0.86 + 0.24 * pool * pool;
  fragColour = vec4(colour, 1.0);
}
