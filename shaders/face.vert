#version 330 core
// The face's vertices in mesh (world) space: positions and normals change every frame, the detail attributes
// (ambient openness; lip weight or opacity) are fixed per mesh. Compiled with the same SKIN / SCLERA / IRIS /
// PLAIN define as face.frag. Skin and plain surfaces are lit here, per vertex: the head's mesh is dense (a
// few pixels between vertices at 720p), so the result matches per-pixel lighting, and a software rasteriser
// shades ten times fewer vertices than pixels. The eyes are lit per pixel (their detail is finer than their
// mesh).
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aDetail;

uniform mat4 uViewProjection;
uniform vec3 uCameraPosition;
uniform vec3 uSpecular;    // linear reflectance at normal incidence
uniform float uShininess;  // Blinn-Phong exponent

out vec3 vPosition;
out vec3 vNormal;
out vec2 vDetail;
#if defined(SKIN) || defined(PLAIN)
out vec3 vDiffuse;   // light that reaches the surface, for the albedo to scale
out vec3 vSpecular;  // light the surface reflects
#endif

void main() {
  vPosition = aPosition;
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
  vDiffuse = diffuseLight(n, wrap) * directOcclusion(open) + ambientLight(n) * open;
#if defined(SKIN)
  // Light that reaches into a crease has bounced off skin on its way: it comes out warm, not as the sky's blue.
  vDiffuse *= mix(vec3(1.0, 0.68, 0.58), vec3(1.0), open);
#endif
  // Highlights need an open view of the light: in creases (seen at grazing angles, where Fresnel would boost
  // them) there is none.
  vSpecular = specularLight(n, v, uShininess, uSpecular) * (open * open);
#endif
  gl_Position = uViewProjection * vec4(aPosition, 1.0);
}
