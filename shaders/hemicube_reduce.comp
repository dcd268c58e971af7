#version 450
// GPU reduction of a hemicube: every pixel adds its delta form factor to its patch's entry of the
// row, in fixed point (integer atomics work everywhere); the first deposit on a patch appends it to
// the touched list, so only the row's nonzeros are read back.
layout(local_size_x = 16, local_size_y = 16) in;

layout(binding = 0, r32ui) readonly uniform uimage2D ids;
layout(std430, binding = 1) readonly buffer Weights { float weight[]; };
layout(std430, binding = 2) buffer Accumulator { uint accumulator[]; };
layout(std430, binding = 3) buffer Touched {
    uint count;
    uint missed;      // pixels that saw nothing
    uint backfaces;   // pixels that saw the back of a patch
    uint lost;        // fixed-point weight of those pixels
    uint roundedLost; // weight of pixels that round to 0 units (lost, not dropped), in units of
                      // 1 / (fixedScale * roundedScale)
    uint list[];
};

uniform uvec2 size;
uniform float fixedScale;  // fixed-point units per unit of form factor
uniform float factor;      // weight multiplier (1, or the mirror chain's product of s)
uniform float roundedScale;  // finer units for sub-unit weights (< 0.5 unit each, so no overflow)

void main() {
    const uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= size.x || p.y >= size.y) return;
    const uint id = imageLoad(ids, ivec2(p)).r;
    const float exact = weight[p.y * size.x + p.x] * factor * fixedScale;
    const uint value = uint(exact + 0.5);
    if (id == 0u || id == 0xffffffffu) {
        if (id == 0u) atomicAdd(missed, 1u);
        else atomicAdd(backfaces, 1u);
        atomicAdd(lost, value);
        return;
    }
    if (value == 0u) {
        // Too small for the fixed point: counted as lost power instead of vanishing.
        if (exact > 0.0) atomicAdd(roundedLost, uint(exact * roundedScale + 0.5));
        return;
    }
    if (atomicAdd(accumulator[id - 1u], value) == 0u) list[atomicAdd(count, 1u)] = id - 1u;
}
