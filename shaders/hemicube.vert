#version 450
// Hemicube pass, vertex stage: passes world positions (scene-centred) and the primitive's code on.
// code = patch id, or (parent index | 0x80000000) for a subdivided parent polygon drawn whole.
// Parent polygons also carry their grid parameters (u, v) and grid (first patch, nu, nv, kind).
layout(location = 0) in vec3 position;
layout(location = 1) in uint code;
layout(location = 2) in vec2 parameter;
layout(location = 3) in uvec4 grid;

out VertexData {
    vec3 position;
    vec2 parameter;
    flat uint code;
    flat uvec4 grid;
} vs;

void main() {
    vs.position = position;
    vs.parameter = parameter;
    vs.code = code;
    vs.grid = grid;
}
