#version 450
// Viewer mirror pass, survey: inside the region being looked into (the stencil test runs before this
// shader), flags each mirror plane whose front faces show there, so that only those are followed.
layout(early_fragment_tests) in;
layout(binding = 0) uniform usampler2D ids;  // the level ids: front faces only, 0 elsewhere
layout(std430, binding = 1) readonly buffer MirrorGroups { uint groupOfPatch[]; };
layout(std430, binding = 5) buffer Seen { uint seen[]; };

void main() {
    const uint id = texelFetch(ids, ivec2(gl_FragCoord.xy), 0).r;
    if (id == 0u) return;
    const uint group = groupOfPatch[id - 1u];
    if (group != 0u) seen[group - 1u] = 1u;
}
