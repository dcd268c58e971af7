#version 450
// Gathers one layer's touched entries (in touched-list order) as (patch, fixed-point value) pairs
// at `offset` of the batch's output, and clears them in the accumulator for the next batch.
layout(local_size_x = 64) in;

layout(std430, binding = 2) buffer Accumulator { uint accumulator[]; };
layout(std430, binding = 3) readonly buffer Touched { uint touched[]; };
layout(std430, binding = 4) writeonly buffer Values { uvec2 values[]; };

uniform uint layer, layers, patches, capacity, offset, count;

void main() {
    const uint k = gl_GlobalInvocationID.x;
    if (k >= count) return;
    const uint j = touched[5u * layers + layer * capacity + k];
    values[offset + k] = uvec2(j, accumulator[layer * patches + j]);
    accumulator[layer * patches + j] = 0u;
}
