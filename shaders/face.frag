#version 330 core
// Shading of the head. The renderer compiles this source once per kind of surface, with one of SKIN, SCLERA,
// IRIS, PLAIN or BROWS (the skin round the eyebrows) defined after the #version line (and lighting.glsl after
// that): a software rasteriser (llvmpipe) runs every branch of a shader, so each program holds only what its
// surface needs. Light is summed in linear space and encoded as sRGB at the end. No textures: the look comes
// from the materials, the per-vertex ambient openness (dark mouth, nostrils, sockets), the skin's markings
// (measured once from its texture coordinates, render/surfaces.h), the brows (drawn here from them) and, for
// the eyes, from the angle round each eye's axis.
#if defined(BROWS)  // the skin round the eyebrows: skin, with the brows drawn over it per pixel
#define SKIN 1
#endif
in vec3 vPosition;
in vec3 vNormal;
in vec2 vDetail;  // x: ambient openness (1 open, 0 enclosed)
#if defined(BROWS)
in vec2 vUv;  // texture coordinates
#endif
#if defined(SKIN) || defined(PLAIN)
in vec4 vColour;  // lit and encoded per vertex (face.vert), premultiplied
#endif

out vec4 fragColour;

uniform vec3 uCameraPosition;
uniform vec3 uAlbedo;      // linear
uniform vec3 uSpecular;    // linear reflectance at normal incidence
uniform float uShininess;  // Blinn-Phong exponent
uniform vec3 uBrowTint;    // skin: the brows' colour over the skin's (sRGB), what they multiply it by

// The eye of this draw (sclera and iris): its centre, its axis (where it looks) and the cosines of the
// pupil's, the iris's and the cornea's angular radii seen from the centre.
uniform vec3 uEyeCentre;
uniform vec3 uEyeAxis;
uniform vec3 uEyeCosines;    // x pupil, y iris, z cornea
uniform vec3 uIrisColour;    // linear
uniform vec3 uScleraColour;  // linear

#if defined(BROWS)
// The eyebrows' cover, 0..1, drawn per pixel from the skin's texture coordinates, so they move with the brows.
// Both at once, mirrored about the face tile's midline. Their line is a parabola through the UVs of ICT
// FaceKit's brow landmarks (iBUG 17-26), lowered a little (those trace the brow's upper part); thick at the
// inner end, tapering to the tail. Hairs: strokes that stand up at the inner end and lie outwards along the
// rest, of random darkness and broken along their length; where a pixel spans several, their average.
float browCover(vec2 uv) {
  float x = abs(uv.x - 0.5);
  float centre = 0.78687 + x * (0.39784 - 1.38716 * x) - 0.007;
  float t = (x - 0.04) / 0.22;  // 0 at the inner end, 1 at the tail
  float dy = uv.y - centre;
  float halfHeight = mix(0.017, 0.0075, t) * (dy > 0.0 ? 1.0 : 0.8);
  float across = 1.0 - smoothstep(0.35, 1.0, abs(dy) / halfHeight);
  float along = smoothstep(-0.08, 0.1, t) * (1.0 - smoothstep(0.75, 1.08, t));
  float angle = mix(1.3, 0.2, smoothstep(0.0, 0.5, t));
  vec2 direction = vec2(cos(angle), sin(angle));
  vec2 p = vec2(x, dy);
  float lanes = dot(p, vec2(-direction.y, direction.x)) * 600.0;  // one hair per unit
  float lane = floor(lanes);
  float run = dot(p, direction) * 600.0 / 5.0 + hash(vec2(lane, 1.0)) * 7.0;
  float hair = (1.0 - abs(fract(lanes) - 0.5) * 2.0) * (0.4 + 0.6 * hash(vec2(lane, 2.0)));
  hair *= step(0.2, fract(run));
  float resolved = 1.0 - smoothstep(0.4, 1.0, fwidth(lanes));  // strokes finer than a pixel average out
  return across * along * mix(0.75, 0.45 + 0.55 * hair, resolved);
}
#endif

void main() {
#if defined(BROWS)
  fragColour = vec4(vColour.rgb * mix(vec3(1.0), uBrowTint, browCover(vUv)), 1.0);
#elif defined(SKIN) || defined(PLAIN)
  fragColour = vColour;
#else
  vec3 n = normalize(vNormal);
  if (!gl_FrontFacing) n = -n;
  vec3 v = normalize(uCameraPosition - vPosition);
  float open = openness(vDetail.x);
  vec3 d = normalize(vPosition - uEyeCentre);
  float c = dot(d, uEyeAxis);
  vec3 albedo;
#if defined(SCLERA)
  if (c > uEyeCosines.z) {
    // The cornea: clear. Only its reflections are drawn, added over the iris (premultiplied blending): sharp
    // glints of the lights and a faint sheen of the surroundings.
    vec3 glint = specularLight(n, v, 900.0, vec3(0.03)) * 2.0;
    glint += ambientLight(reflect(-v, n)) * (0.03 + 0.97 * schlick(dot(n, v))) * 0.5;
    fragColour = vec4(finish(glint * open), 0.0);
    return;
  }
  // The white of the eye: slightly warmer and darker towards the corners.
  albedo = mix(uAlbedo, uAlbedo * vec3(0.93, 0.78, 0.74), smoothstep(0.55, 0.05, c));
#else  // IRIS
  if (c > uEyeCosines.y) {
    float angle = acos(clamp(c, -1.0, 1.0));
    float pupil = acos(uEyeCosines.x);
    float iris = acos(uEyeCosines.y);
    float t = clamp((angle - pupil) / max(iris - pupil, 1e-4), 0.0, 1.0);
    // Radial fibres: the angle round the axis, in a frame that does not depend on the eye's roll.
    vec3 side = normalize(cross(uEyeAxis, abs(uEyeAxis.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0)));
    vec3 up = cross(side, uEyeAxis);
    float around = atan(dot(d, up), dot(d, side));
    float fibres = 0.5 + 0.5 * sin(around * 41.0 + 3.0 * sin(around * 7.0) + 9.0 * t);
    vec3 inner = uIrisColour * vec3(1.4, 1.2, 0.75);  // a warmer ring round the pupil
    albedo = mix(inner, uIrisColour, smoothstep(0.1, 0.45, t)) * (0.72 + 0.4 * fibres);
    albedo *= 1.0 - 0.7 * smoothstep(0.7, 1.0, t);  // the dark limbal ring
    float edge = fwidth(angle) * 1.5;
    albedo = mix(vec3(0.003), albedo, smoothstep(pupil - edge, pupil + edge, angle));
  } else {
    // The eyeball round the iris, mostly hidden by the sclera; its back half is only ever seen through the
    // pupil (ICT FaceKit's pupil is a hole in the iris): the dark inside of the eye.
    albedo = c > 0.0 ? uScleraColour * 0.8 : vec3(0.0);
  }
#endif
  vec3 colour = albedo * (diffuseLight(n, vec3(0.0)) * directOcclusion(open) + ambientLight(n) * open);
  colour += specularLight(n, v, uShininess, uSpecular) * open;
  fragColour = vec4(finish(colour), 1.0);
#endif
}
