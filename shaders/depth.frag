#version 330 core
// Depth only: nothing to write but the depth the rasteriser computes.
void main() {}
