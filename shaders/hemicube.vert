#version 450
// Hemicube pass, vertex stage: moves each vertex into the patch frame (x along t, y along b,
// z along the normal, origin at the hemicube centre) once, so the geometry stage builds the five
// faces' clip coordinates by swizzles instead of five matrix products per vertex.
// code = patch id, or (parent index | 0x80000000) for a subdivided parent polygon drawn whole;
// parent polygons also carry their grid parameter (u, v) and grid (first patch, nu, nv, kind).
// One instance per hemicube of a batch: instance k draws into layer k of the atlas array with the
// k-th hemicube's frame (a single hemicube, or a portal pass, is a batch of one).
layout(location = 0) in vec3 position;
layout(location = 1) in uint code;
layout(location = 2) in vec2 parameter;
layout(location = 3) in uvec4 grid;

struct Hemicube {
    mat4 frameFromWorld;  // world -> patch frame, including a portal's reflections
    uvec4 codes;          // x: the code under which the hemicube's own patch is drawn
};
layout(std430, binding = 5) readonly buffer Hemicubes {
    Hemicube hemicubes[];
};
uniform vec4 clipPlane;       // world half-space kept (mirror passes); (0, 0, 0, 1) keeps everything

out VertexData {
    vec3 frame;
    float clip;
    vec2 parameter;
    flat uint code;
    flat uvec4 grid;
    flat int layer;
} vs;

void main() {
    vs.frame = (hemicubes[gl_InstanceID].frameFromWorld * vec4(position, 1.0)).xyz;
    vs.layer = gl_InstanceID;
    vs.clip = dot(clipPlane, vec4(position, 1.0));
    vs.parameter = parameter;
    vs.code = code;
    vs.grid = grid;
}
