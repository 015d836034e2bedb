#version 450 core
// Depth only (reversed Z: depth = near / z is written by the rasteriser).
void main() {}
