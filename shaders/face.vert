#version 330 core
// The face's vertices in mesh (world) space: positions and normals change every frame, the detail attributes
// (ambient openness; lip weight or opacity; texture coordinates) are fixed per mesh. Compiled with the same
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
// Where blood shows through (ICT FaceKit's face tile, mirrored about its midline u = 0.5): the cheeks below
// the eyes and the nose's tip; 0..1.
float flush(vec2 uv) {
  vec2 cheek = (vec2(abs(uv.x - 0.5), uv.y) - vec2(0.155, 0.6)) / vec2(0.06, 0.045);
  vec2 nose = (uv - vec2(0.5, 0.612)) / 0.025;
  return 0.5 * exp(-dot(cheek, cheek)) + 0.3 * exp(-dot(nose, nose));
}

// The short hair's cover, 0..1, from ICT FaceKit's UV tiles: on the face's (u 0..1) above a hairline across
// the top of the forehead that drops at the temples to sideburns in front of the ears; on the back of the
// head's (u 1..2) the scalp, from above the ears round to the nape. That tile's outer parts are the neck and
// shoulders, and its top corners hold hidden patches inside the eye sockets: no hair there.
float hairCover(vec2 uv) {
  if (uv.x < 1.0) {
    float hairline = 0.95 - 0.12 * smoothstep(0.22, 0.42, abs(uv.x - 0.5));
    hairline += 0.004 * sin(uv.x * 160.0) * sin(uv.x * 37.0);  // not a ruled line
    return smoothstep(hairline - 0.01, hairline + 0.01, uv.y);
  }
  float s = abs(uv.x - 1.5);
  float nape = 0.4 + 1.8 * s * s;
  float scalp = smoothstep(nape - 0.02, nape + 0.02, uv.y) * (1.0 - smoothstep(0.33, 0.36, s));
  return scalp * (1.0 - smoothstep(0.215, 0.23, s) * smoothstep(0.78, 0.8, uv.y));
}

// The skin's albedo at a vertex: blotchy at the centimetre scale (red and yellow varying apart, as skin's
// blood and pigment do), flushed on the cheeks, the lips' red mixed in by their weight.
vec3 skinAlbedo(vec2 uv, float lip, float hairCover) {
  float blotch = valueNoise(uv * 30.0) - 0.5;
  vec3 albedo = uAlbedo * vec3(1.0 + 0.03 * blotch, 1.0 - 0.06 * blotch, 1.0 - 0.08 * blotch);
  albedo = mix(albedo, albedo * vec3(1.0, 0.74, 0.72), flush(uv));
  albedo = mix(albedo, uLipAlbedo, lip);
  // Cropped hair: its colour with the scalp showing through a little, varying from vertex to vertex.
  vec3 hair = uHairAlbedo * (0.75 + 0.5 * hash(uv * 311.0));
  return mix(albedo, hair, 0.92 * hairCover);
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
  float hair = hairCover(aUv);
  vec3 specular = specularLight(n, v, mix(uShininess, 70.0, lip), mix(uSpecular, vec3(0.06), lip)) * (open * open);
  specular *= mix(0.45 + 0.9 * hash(aUv * 173.0), 1.0, lip) * (1.0 - 0.6 * hair);
  vColour = vec4(finish(skinAlbedo(aUv, lip, hair) * diffuse + specular), 1.0);
#else
  vec3 specular = specularLight(n, v, uShininess, uSpecular) * (open * open);
  float alpha = uOpacity * aDetail.y;
  vColour = vec4(finish(uAlbedo * diffuse + specular) * alpha, alpha);
#endif
#endif
  gl_Position = uViewProjection * vec4(aPosition, 1.0);
}
