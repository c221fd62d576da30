#version 330 core
// Depth only: the views from many directions that the per-vertex ambient occlusion is measured with.
layout(location = 0) in vec3 aPosition;

uniform mat4 uViewProjection;

void main() { gl_Position = uViewProjection * vec4(aPosition, 1.0); }
