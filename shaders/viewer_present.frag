#version 450
// Viewer present pass: shows one layer of the offscreen target in the window, tone-mapped where it
// holds radiance, with the selection outlined and the hovered patch highlighted.
in vec2 uv;
layout(binding = 0) uniform usampler2D ids;
layout(binding = 1) uniform sampler2D layerTexture;
layout(std430, binding = 2) readonly buffer PatchFlags {
    uint flags[];        // bit 0 selected
};
layout(std430, binding = 3) readonly buffer RowValues { float rowValue[]; };
layout(std430, binding = 4) readonly buffer FalseColours { uint falseColour[]; };  // 0xRRGGBB per patch

uniform int layer;        // 0 radiance, 1 patch id, 2 emission, 3 reflectance, 4 specular, 5 F row, 6 false colour
uniform float exposure;
uniform uint hovered;     // patch id + 1, 0 = none
uniform float rowMax;     // largest F_ij of the inspected row (log colour scale)
uniform bool anySelected; // some patch is selected: look for the outline

out vec4 color;

vec3 srgb(vec3 linear) {
    const vec3 c = clamp(linear, 0.0, 1.0);
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

vec3 hashColor(uint id) {
    uint h = id * 2654435761u;
    return vec3(float((h >> 16) & 255u), float((h >> 8) & 255u), float(h & 255u)) / 255.0 * 0.8 + 0.2;
}

// Perceptual ramp (dark blue -> yellow) for form factors on a log scale over 4 decades.
vec3 ramp(float t) {
    return clamp(vec3(-0.3 + 1.6 * t, 0.1 + 0.9 * t * (1.4 - t) + 0.3 * t, 0.6 - 0.5 * t + 0.3 * (1.0 - t)), 0.0, 1.0);
}

bool selectedAt(ivec2 q) {
    const uint i = texelFetch(ids, clamp(q, ivec2(0), textureSize(ids, 0) - 1), 0).r;
    return i != 0u && (flags[i - 1u] & 1u) != 0u;
}

// The selection's outline, drawn outside it so that its own pixels keep their colour (a false-colour
// value stays readable against the legend): 2 px of orange, then 1 px of black, so that it shows on
// the map's yellow and on a dark background alike. 0: no outline here, 1 orange, 2 black.
int outline(ivec2 p) {
    if (!anySelected || selectedAt(p)) return 0;
    int nearest = 4;  // Chebyshev distance to the nearest selected pixel, up to 3
    for (int dy = -3; dy <= 3; ++dy)
        for (int dx = -3; dx <= 3; ++dx) {
            const int d = max(abs(dx), abs(dy));
            if (d < nearest && selectedAt(p + ivec2(dx, dy))) nearest = d;
        }
    return nearest <= 2 ? 1 : nearest == 3 ? 2 : 0;
}

void main() {
    const ivec2 p = ivec2(gl_FragCoord.xy);
    const uint id = texelFetch(ids, p, 0).r;
    vec3 c;
    if (layer == 1) {
        c = id == 0u ? vec3(0.0) : hashColor(id);
    } else if (layer == 6) {
        // The colour map was applied per patch on the CPU (sRGB bytes, as hemirad render's).
        const uint v = id == 0u ? 0u : falseColour[id - 1u];
        c = vec3(float((v >> 16) & 255u), float((v >> 8) & 255u), float(v & 255u)) / 255.0;
    } else if (layer == 5) {
        const float v = id == 0u ? 0.0 : rowValue[id - 1u];
        c = v > 0.0 ? ramp(clamp(1.0 + log(v / rowMax) / log(10000.0), 0.0, 1.0)) : vec3(0.05);
    } else {
        const vec3 value = texelFetch(layerTexture, p, 0).rgb;
        c = (layer == 0 || layer == 2) ? srgb(value * exposure) : value;
    }
    if (id != 0u && id == hovered) c = mix(c, vec3(1.0), 0.25);
    const int edge = outline(p);
    if (edge == 1) c = vec3(1.0, 0.35, 0.0);
    else if (edge == 2) c = vec3(0.0);
    color = vec4(c, 1.0);
}
