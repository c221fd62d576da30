#version 330 core
// The face's vertices in mesh (world) space: positions and normals change every frame, the detail attributes
// (ambient openness; lip weight or opacity) are fixed per mesh. Compiled with the same SKIN / SCLERA / IRIS /
// PLAIN define as face.frag. Skin and plain surfaces are lit and finished here, per vertex (tone curve and sRGB
// encoding included, so their fragment shader only passes the colour on): the head's mesh is dense (a few
// pixels between vertices at 720p), so the result matches per-pixel shading (the golden images did not
// move beyond their tolerance), and a software rasteriser shades ten times fewer vertices than pixels. The
// eyes are lit per pixel (their detail is finer than their mesh).
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aDetail;

uniform mat4 uViewProjection;
uniform vec3 uCameraPosition;
uniform vec3 uAlbedo;      // linear
uniform vec3 uLipAlbedo;   // linear, mixed in by the lip weight (skin)
uniform vec3 uSpecular;    // linear reflectance at normal incidence
uniform float uShininess;  // Blinn-Phong exponent
uniform float uOpacity;

out vec3 vPosition;
out vec3 vNormal;
out vec2 vDetail;
#if defined(SKIN) || defined(PLAIN)
out vec4 vColour;  // the finished colour, premultiplied: the fragment shader only passes it on
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
  vec3 diffuse = diffuseLight(n, wrap) * directOcclusion(open) + ambientLight(n) * open;
#if defined(SKIN)
  // Light that reaches into a crease has bounced off skin on its way: it comes out warm, not as the sky's blue.
  diffuse *= mix(vec3(1.0, 0.68, 0.58), vec3(1.0), open);
#endif
  // Highlights need an open view of the light: in creases (seen at grazing angles, where Fresnel would boost
  // them) there is none.
  vec3 specular = specularLight(n, v, uShininess, uSpecular) * (open * open);
#if defined(SKIN)
  vColour = vec4(finish(mix(uAlbedo, uLipAlbedo, aDetail.y) * diffuse + specular), 1.0);
#else
  float alpha = uOpacity * aDetail.y;
  vColour = vec4(finish(uAlbedo * diffuse + specular) * alpha, alpha);
#endif
#endif
  gl_Position = uViewProjection * vec4(aPosition, 1.0);
}
