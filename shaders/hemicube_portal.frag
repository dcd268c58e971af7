#version 450
// Mirror portal marking, fragment stage: keeps the pixels that saw a patch of the mirror plane
// `group` in the previous level's ids, so the stencil test marks them, and resets them for the
// reflected view: id 0 (nothing seen yet) and the far depth (0 in reversed Z).
layout(binding = 0) uniform usampler2D levelIds;
layout(std430, binding = 1) readonly buffer MirrorGroups {
    uint groupOfPatch[];  // mirror plane group + 1 per patch, 0 for non-mirrors
};
uniform uint group;

layout(location = 0) out uint id;

void main() {
    const uint seen = texelFetch(levelIds, ivec2(gl_FragCoord.xy), 0).r;
    if (seen == 0u || seen == 0xffffffffu || groupOfPatch[seen - 1u] != group + 1u) discard;
    id = 0u;
    gl_FragDepth = 0.0;
}
