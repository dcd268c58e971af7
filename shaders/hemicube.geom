#version 450
// Hemicube pass, geometry stage: each triangle goes to the five faces of the hemicube in one draw
// (Cohen & Greenberg 1985), one viewport of the 3R x R atlas per face. Triangles of the patch
// itself, behind its plane, or outside a face's frustum are dropped here. (Measured on llvmpipe:
// twice as fast for a 6,348-triangle scene as one instanced draw whose vertex stage picks the
// viewport and leaves all culling to the clipper.) Each instance is one hemicube of a batch,
// drawn into its own layer of the atlas array.
//
// Face cameras in the patch frame (x, y, z) = (t, b, n), reversed Z with an infinite far plane:
//   top  (looks along  n): clip = (-x, y,      near,  z)   [x, y in [-1, 1] at z = 1]
//   +t side (along  t):    clip = (-y, 2z - x, near,  x)   [elevation z in [0, 1] at x = 1]
//   -t side (along -t):    clip = ( y, 2z + x, near, -x)
//   +b side (along  b):    clip = ( x, 2z - y, near,  y)
//   -b side (along -b):    clip = (-x, 2z + y, near, -y)
layout(triangles, invocations = 1) in;
layout(triangle_strip, max_vertices = 15) out;

in VertexData {
    vec3 frame;
    float clip;
    vec2 parameter;
    flat uint code;
    flat uvec4 grid;
    flat int layer;
} gs[];

struct Hemicube {
    mat4 frameFromWorld;
    uvec4 codes;  // x: the code under which the hemicube's own patch is drawn (skipped)
};
layout(std430, binding = 5) readonly buffer Hemicubes {
    Hemicube hemicubes[];
};
uniform float planeEpsilon;   // elevation below which a vertex counts as on the patch plane
uniform float nearPlane;

#ifndef HEMICUBE_KIND
#define HEMICUBE_KIND 0
#endif
flat out uint fragCode;
#if HEMICUBE_KIND != 0
flat out uvec2 fragGrid;  // first patch, nu | nv << 16
out vec2 fragParameter;
#endif
out float gl_ClipDistance[1];

void emitFace(int face, uint code, vec4 c0, vec4 c1, vec4 c2) {
    // Entirely outside one plane of the face frustum (x, y in [-w, w], w >= near): skip.
    if (c0.w < nearPlane && c1.w < nearPlane && c2.w < nearPlane) return;
    if (c0.x < -c0.w && c1.x < -c1.w && c2.x < -c2.w) return;
    if (c0.x > c0.w && c1.x > c1.w && c2.x > c2.w) return;
    if (c0.y < -c0.w && c1.y < -c1.w && c2.y < -c2.w) return;
    if (c0.y > c0.w && c1.y > c1.w && c2.y > c2.w) return;
    const vec4 c[3] = vec4[3](c0, c1, c2);
    for (int k = 0; k < 3; ++k) {
        gl_Position = c[k];
        gl_ViewportIndex = face;
        gl_Layer = gs[0].layer;
        gl_ClipDistance[0] = gs[k].clip;
        fragCode = code;
#if HEMICUBE_KIND != 0
        fragGrid = uvec2(gs[0].grid.x, gs[0].grid.y | (gs[0].grid.z << 16));
        fragParameter = gs[k].parameter;
#endif
        EmitVertex();
    }
    EndPrimitive();
}

void main() {
    const uint code = gs[0].code;
    if (code == hemicubes[gs[0].layer].codes.x) return;
    const vec3 a = gs[0].frame, b = gs[1].frame, c = gs[2].frame;
    if (max(a.z, max(b.z, c.z)) <= planeEpsilon) return;
    const float n = nearPlane;
    // Written out per face (straight-line code: llvmpipe runs every branch of a loop body masked).
    emitFace(0, code, vec4(-a.x, a.y, n, a.z), vec4(-b.x, b.y, n, b.z), vec4(-c.x, c.y, n, c.z));
    emitFace(1, code, vec4(-a.y, 2.0 * a.z - a.x, n, a.x), vec4(-b.y, 2.0 * b.z - b.x, n, b.x),
             vec4(-c.y, 2.0 * c.z - c.x, n, c.x));
    emitFace(2, code, vec4(a.y, 2.0 * a.z + a.x, n, -a.x), vec4(b.y, 2.0 * b.z + b.x, n, -b.x),
             vec4(c.y, 2.0 * c.z + c.x, n, -c.x));
    emitFace(3, code, vec4(a.x, 2.0 * a.z - a.y, n, a.y), vec4(b.x, 2.0 * b.z - b.y, n, b.y),
             vec4(c.x, 2.0 * c.z - c.y, n, c.y));
    emitFace(4, code, vec4(-a.x, 2.0 * a.z + a.y, n, -a.y), vec4(-b.x, 2.0 * b.z + b.y, n, -b.y),
             vec4(-c.x, 2.0 * c.z + c.y, n, -c.y));
}
