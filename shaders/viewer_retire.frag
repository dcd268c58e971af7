#version 450
// Viewer mirror pass, retire: writes nothing but the stencil (set by the stencil operation), so a
// finished portal's pixels match no later portal test.
void main() {}
