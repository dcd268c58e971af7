#version 450
// Hemicube pass, fragment stage: writes the patch id + 1 seen in each pixel; 0xffffffff for the
// back of a patch (power lost), 0 (the clear value) where nothing is hit. A parent polygon's
// fragment finds its patch from its place in the parent's subdivision grid: for parallelograms
// and triangles the interpolated grid parameter (affine, so exact); for other planar quads the
// parameter is the position in the parent's plane and the inverse bilinear map gives (u, v).
#ifndef HEMICUBE_KIND
#define HEMICUBE_KIND 0
#endif
flat in uint fragCode;
#if HEMICUBE_KIND != 0
flat in uvec2 fragGrid;   // first patch, nu | nv << 16
in vec2 fragParameter;
#endif

layout(location = 0) out uint id;

struct Parent {
    vec4 q12;      // corners 1 and 2 in the parent's plane (corner 0 at the origin)
    vec4 q3;       // corner 3
};
layout(std430, binding = 0) readonly buffer Parents {
    Parent parents[];
};

// The program is built once per kind of primitive (llvmpipe evaluates untaken branches under a
// mask, so one shader for all kinds cost every fragment the dearest path: measured 2.6x slower).
//   0: patch triangles (code = patch id)   1: parallelogram parents   2: triangle parents
//   3: other planar quad parents (parameter = planar position, inverse bilinear map)

#if HEMICUBE_KIND == 3
float cross2(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

// Inverse of the bilinear map (0, q1, q2, q3) -> p, for planar quads (straight iso-lines).
vec2 inverseBilinear(vec2 p, vec2 b, vec2 c, vec2 d) {
    const vec2 e = b, f = d, g = -b + c - d, h = p;
    const float k2 = cross2(g, f);
    const float k1 = cross2(e, f) + cross2(h, g);
    const float k0 = cross2(h, e);
    float v;
    if (abs(k2) <= 1e-6 * abs(k1)) {
        v = -k0 / k1;
    } else {
        const float w = sqrt(max(k1 * k1 - 4.0 * k0 * k2, 0.0));
        v = (-k1 - w) / (2.0 * k2);
        if (v < -0.01 || v > 1.01) v = (-k1 + w) / (2.0 * k2);
    }
    const vec2 denominator = e + g * v;
    const float u = abs(denominator.x) >= abs(denominator.y) ? (h.x - f.x * v) / denominator.x
                                                             : (h.y - f.y * v) / denominator.y;
    return vec2(u, v);
}
#endif

uint quadCell(vec2 uv, uint nu, uint nv) {
    const uint i = uint(clamp(int(floor(uv.x * float(nu))), 0, int(nu) - 1));
    const uint j = uint(clamp(int(floor(uv.y * float(nv))), 0, int(nv) - 1));
    return j * nu + i;
}

// Barycentric (a, b) on a triangle grid of n rows: row j holds 2 (n - j) - 1 cells, up and down.
uint triangleCell(vec2 ab, uint nu) {
    const int n = int(nu);
    const vec2 x = ab * float(n);
    const int j = clamp(int(floor(x.y)), 0, n - 1);
    const int a = clamp(int(floor(x.x)), 0, n - 1 - j);
    const bool up = (x.x - float(a)) + (x.y - float(j)) < 1.0 || a + j == n - 1;
    return uint(j * (2 * n - j) + 2 * a + (up ? 0 : 1));
}

void main() {
    if (!gl_FrontFacing) {
        id = 0xffffffffu;
        return;
    }
#if HEMICUBE_KIND == 0
    id = 1u + fragCode;
#else
    const uint first = fragGrid.x, nu = fragGrid.y & 0xffffu, nv = fragGrid.y >> 16;
#if HEMICUBE_KIND == 1
    id = 1u + first + quadCell(fragParameter, nu, nv);
#elif HEMICUBE_KIND == 2
    id = 1u + first + triangleCell(fragParameter, nu);
#else
    const Parent P = parents[fragCode & 0x7fffffffu];
    id = 1u + first + quadCell(inverseBilinear(fragParameter, P.q12.xy, P.q12.zw, P.q3.xy), nu, nv);
#endif
#endif
}
