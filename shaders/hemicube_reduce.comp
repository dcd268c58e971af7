#version 450
// GPU reduction of a batch of hemicubes, one atlas layer each: every pixel adds its delta form
// factor to its patch's entry of its layer's row, in fixed point (integer atomics work
// everywhere); the first deposit on a patch appends it to the layer's touched list, so only the
// rows' nonzeros are read back.
layout(local_size_x = 16, local_size_y = 16) in;

layout(binding = 0, r32ui) readonly uniform uimage2DArray ids;
layout(std430, binding = 1) readonly buffer Weights { float weight[]; };
layout(std430, binding = 2) buffer Accumulator { uint accumulator[]; };  // [layer][patch]
// Per layer a header of 5 counters, the atlas's headers first (whatever the pass's layer count,
// so a smaller pass leaves nothing where a larger one keeps headers), then the touched lists
// [layer][capacity]:
//   count | missed (pixels that saw nothing) | backfaces | lost (fixed-point weight of those) |
//   roundedLost (pixels below one unit, in units of 1 / (fixedScale * roundedScale))
layout(std430, binding = 3) buffer Touched { uint touched[]; };

uniform uvec2 size;
uniform uint patches;        // row length
uniform uint atlasLayers;    // layers of the atlas (header block size / 5)
uniform uint capacity;       // touched-list length per layer
uniform float fixedScale;    // fixed-point units per unit of form factor
uniform float roundedScale;  // finer units for sub-unit weights (< 0.5 unit each, so no overflow)

void main() {
    const uvec3 p = gl_GlobalInvocationID;
    if (p.x >= size.x || p.y >= size.y) return;
    const uint id = imageLoad(ids, ivec3(p)).r;
    const float exact = weight[p.y * size.x + p.x] * fixedScale;
    const uint value = uint(exact + 0.5);
    const uint header = 5u * p.z;
    if (id == 0u || id == 0xffffffffu) {
        if (id == 0u) atomicAdd(touched[header + 1u], 1u);
        else atomicAdd(touched[header + 2u], 1u);
        atomicAdd(touched[header + 3u], value);
        return;
    }
    if (value == 0u) {
        // Too small for the fixed point: counted as lost power instead of vanishing.
        if (exact > 0.0) atomicAdd(touched[header + 4u], uint(exact * roundedScale + 0.5));
        return;
    }
    if (atomicAdd(accumulator[p.z * patches + id - 1u], value) == 0u)
        touched[5u * atlasLayers + p.z * capacity + atomicAdd(touched[header], 1u)] = id - 1u;
}
