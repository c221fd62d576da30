#version 330 core
// One triangle that covers the screen, made from gl_VertexID alone (no vertex buffer). It lies on the far
// plane and is drawn after the opaque head with GL_LEQUAL, so only the pixels (samples) the head left empty
// are shaded.
out vec2 vUv;

void main() {
  vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  vUv = corner;
  gl_Position = vec4(corner * 2.0 - 1.0, 1.0, 1.0);
}
