#version 450
// Between the GPU reduction's two passes: each layer's touched count becomes its place in the
// pass's output (an exclusive prefix sum over the layers), the headers are copied to the output
// and cleared for the next pass, and the gather's indirect dispatch is sized by the longest list,
// so the CPU never waits in the middle of a pass.
layout(local_size_x = 256) in;

layout(std430, binding = 3) buffer Touched { uint touched[]; };  // headers first (5 per layer)
// [0..2]: the gather's dispatch (groups x = ceil(longest / 64) up to 65535, y = layers, 1); then per layer
// (count, offset).
layout(std430, binding = 6) writeonly buffer Plan { uint plan[]; };
// The pass's host-visible output: headers (5 per layer), offsets (layers + 1), then the pairs.
layout(std430, binding = 4) writeonly buffer Output { uint outputWords[]; };

uniform uint layers;

shared uint partial[256];
shared uint longest[256];

void main() {
    const uint t = gl_LocalInvocationID.x;
    const uint chunk = (layers + 255u) / 256u;
    const uint first = min(layers, t * chunk), last = min(layers, first + chunk);
    uint sum = 0u, most = 0u;
    for (uint l = first; l < last; ++l) {
        sum += touched[5u * l];
        most = max(most, touched[5u * l]);
    }
    partial[t] = sum;
    longest[t] = most;
    memoryBarrierShared();
    barrier();
    // Inclusive scan of the chunk sums (Hillis & Steele), and the longest list.
    for (uint step = 1u; step < 256u; step <<= 1) {
        const uint add = t >= step ? partial[t - step] : 0u;
        const uint other = longest[t ^ step];
        barrier();
        partial[t] += add;
        longest[t] = max(longest[t], other);
        memoryBarrierShared();
        barrier();
    }
    uint offset = partial[t] - sum;
    for (uint l = first; l < last; ++l) {
        const uint count = touched[5u * l];
        plan[3u + 2u * l] = count;
        plan[4u + 2u * l] = offset;
        outputWords[5u * layers + l] = offset;
        for (uint h = 0u; h < 5u; ++h) {
            outputWords[5u * l + h] = touched[5u * l + h];
            touched[5u * l + h] = 0u;
        }
        offset += count;
    }
    if (t == 255u) outputWords[6u * layers] = offset;
    if (t == 0u) {
        plan[0] = min((longest[0] + 63u) / 64u, 65535u);  // the minimum limit; the gather strides beyond
        plan[1] = layers;
        plan[2] = 1u;
    }
}
