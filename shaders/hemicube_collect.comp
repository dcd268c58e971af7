#version 450
// Gathers every layer's touched entries (in touched-list order) as (patch, fixed-point value)
// pairs at the layer's offset in the pass's host-visible output, and clears them in the
// accumulator for the next pass. Dispatched indirectly (hemicube_plan.comp): groups x cover the
// longest list, y is the layer.
layout(local_size_x = 64) in;

layout(std430, binding = 2) buffer Accumulator { uint accumulator[]; };
layout(std430, binding = 3) readonly buffer Touched { uint touched[]; };
layout(std430, binding = 6) readonly buffer Plan { uint plan[]; };
layout(std430, binding = 4) writeonly buffer Output { uint outputWords[]; };

uniform uint layers, atlasLayers, patches, capacity;

void main() {
    const uint layer = gl_WorkGroupID.y;
    const uint count = plan[3u + 2u * layer], offset = plan[4u + 2u * layer];
    // Strided: a list longer than 65535 groups of 64 (the dispatch's guaranteed limit) still ends.
    for (uint k = gl_GlobalInvocationID.x; k < count; k += gl_NumWorkGroups.x * 64u) {
        const uint j = touched[5u * atlasLayers + layer * capacity + k];
        const uint pair = 6u * layers + 1u + 2u * (offset + k);
        outputWords[pair] = j;
        outputWords[pair + 1u] = accumulator[layer * patches + j];
        accumulator[layer * patches + j] = 0u;
    }
}
