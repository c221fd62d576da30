#version 330 core
// The face's vertices in mesh (world) space: positions and normals change every frame, the detail attributes
// (ambient openness; lip weight or opacity; texture coordinates; the skin's markings) are fixed per mesh. Compiled with the same
// SKIN / SCLERA / IRIS / PLAIN / BROWS define as face.frag. Skin and plain surfaces are lit and finished here, per vertex (tone curve and sRGB
// encoding included, so their fragment shader only passes the colour on): the head's mesh is dense (a few
// pixels between vertices at 720p), so the result matches per-pixel shading (the golden images did not
// move beyond their tolerance), and a software rasteriser shades ten times fewer vertices than pixels. The
// eyes are lit per pixel (their detail is finer than their mesh).
#if defined(BROWS)  // the skin round the eyebrows: skin, with the brows drawn over it per pixel
#define SKIN 1
#endif
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aDetail;
layout(location = 3) in vec2 aUv;  // texture coordinates (ICT FaceKit's layout: the face's tile is u in 0..1)
layout(location = 4) in vec3 aSkin;  // the skin's markings: redness, hair, grain (render/surfaces.h)

uniform mat4 uViewProjection;
uniform vec3 uCameraPosition;
uniform vec3 uAlbedo;      // linear
uniform vec3 uLipAlbedo;   // linear, mixed in by the lip weight (skin)
uniform vec3 uHairAlbedo;  // linear, the short hair on the scalp (skin)
uniform vec3 uSpecular;    // linear reflectance at normal incidence
uniform float uShininess;  // Blinn-Phong exponent
uniform float uOpacity;

out vec3 vPosition;
out vec3 vNormal;
out vec2 vDetail;
out vec2 vUv;
#if defined(SKIN) || defined(PLAIN)
out vec4 vColour;  // the finished colour, premultiplied: the fragment shader only passes it on
#endif

#if defined(SKIN)
// The skin's albedo at a vertex: redder by its markings (blotches, cheeks, nose), the lips' red mixed in by
// their weight, cropped hair over the scalp (its colour with the scalp showing through a little).
vec3 skinAlbedo(float lip) {
  vec3 albedo = uAlbedo * (vec3(1.0) - vec3(0.0, 0.26, 0.28) * aSkin.x);
  albedo = mix(albedo, uLipAlbedo, lip);
  return mix(albedo, uHairAlbedo * (0.75 + 0.5 * aSkin.z), 0.92 * aSkin.y);
}
#endif

void main() {
  vPosition = aPosition;
  vUv = aUv;
  vNormal = aNormal;
  vDetail = aDetail;
#if defined(SKIN) || defined(PLAIN)
  vec3 n = normalize(aNormal);
  vec3 v = normalize(uCameraPosition - aPosition);
  float open = openness(aDetail.x);
#if defined(SKIN)
  vec3 wrap = vec3(0.42, 0.25, 0.2);
#else
  // Cards (lashes) are seen from both sides: light the side that faces the camera.
  if (dot(n, v) < 0.0) n = -n;
  vec3 wrap = vec3(0.3, 0.22, 0.2);
#endif
  vec3 diffuse = diffuseLight(n, wrap) * directOcclusion(open) + ambientLight(n) * open;
#if defined(SKIN)
  // Light that reaches into a crease has bounced off skin on its way: it comes out warm, not as the sky's blue.
  diffuse *= mix(vec3(1.0, 0.68, 0.58), vec3(1.0), open);
  // Towards the key light's terminator what light remains has scattered under the skin, losing its green and
  // blue to blood: the falloff turns red instead of grey.
  diffuse *= mix(vec3(1.0, 0.8, 0.72), vec3(1.0), smoothstep(-0.1, 0.55, dot(n, uLightDirection[0])));
#endif
  // Highlights need an open view of the light: in creases (seen at grazing angles, where Fresnel would boost
  // them) there is none.
#if defined(SKIN)
  float lip = smoothstep(0.0, 0.75, aDetail.y);  // a fuller red, its border still soft
  // Skin's sheen is broken up by pores and fine lines: its strength varies from vertex to vertex (a few
  // millimetres apart); the lips are wet, with a tighter, brighter highlight; hair is matte.
  vec3 specular = specularLight(n, v, mix(uShininess, 70.0, lip), mix(uSpecular, vec3(0.06), lip)) * (open * open);
  specular *= mix(0.6 + 0.6 * aSkin.z, 1.0, lip) * (1.0 - 0.6 * aSkin.y);
  vColour = vec4(finish(skinAlbedo(lip) * diffuse + specular), 1.0);
#else
  vec3 specular = specularLight(n, v, uShininess, uSpecular) * (open * open);
  float alpha = uOpacity * aDetail.y;
  vColour = vec4(finish(uAlbedo * diffuse + specular) * alpha, alpha);
#endif
#endif
  gl_Position = uViewProjection * vec4(aPosition, 1.0);
}
