// A character's vertices in the scene's space (posed and skinned on the CPU: avatar/avatar_pose.h), with their
// texture coordinates. Prepended: #version, the shared lighting code (lighting.glsl).
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv;

uniform mat4 uViewProjection;

invariant gl_Position;  // the same depth in the depth pass and the shading pass (different programs)

out vec3 vPosition;
out vec3 vNormal;
out vec2 vUv;

void main() {
  vPosition = aPosition;
  vNormal = aNormal;
  vUv = aUv;
  gl_Position = uViewProjection * vec4(aPosition, 1.0);
}
