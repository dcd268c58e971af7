#version 450
// Gathers the touched entries of the GPU row (in touched-list order) and clears them for the next row.
layout(local_size_x = 64) in;

layout(std430, binding = 2) buffer Accumulator { uint accumulator[]; };
layout(std430, binding = 3) readonly buffer Touched {
    uint count;
    uint missed;
    uint backfaces;
    uint lost;
    uint roundedLost;
    uint list[];
};
layout(std430, binding = 4) writeonly buffer Values { uint values[]; };

void main() {
    const uint k = gl_GlobalInvocationID.x;
    if (k >= count) return;
    const uint j = list[k];
    values[k] = accumulator[j];
    accumulator[j] = 0u;
}
