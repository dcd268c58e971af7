#version 450
// Viewer mirror pass, marking: keeps the pixels showing a front face of one mirror plane (so the
// stencil marks them) and resets their depth to the far plane for the reflected scene.
layout(binding = 0) uniform usampler2D ids;  // the level ids: front faces only, 0 elsewhere
layout(std430, binding = 1) readonly buffer MirrorGroups { uint groupOfPatch[]; };
uniform uint group;

void main() {
    const uint id = texelFetch(ids, ivec2(gl_FragCoord.xy), 0).r;
    if (id == 0u || groupOfPatch[id - 1u] != group + 1u) discard;
    gl_FragDepth = 1.0;
}
