#version 450
// One photon counted in its density cell.
layout(location = 0) out float count;
void main() { count = 1.0; }
