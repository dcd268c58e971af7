#version 450
// Hemicube pass, geometry stage: each triangle goes to the five faces of the hemicube in one draw
// (Cohen & Greenberg 1985), one viewport of the 3R x R atlas per face. Triangles of the patch
// itself, behind its plane, or outside a face's frustum are dropped here.
layout(triangles, invocations = 1) in;
layout(triangle_strip, max_vertices = 15) out;

in VertexData {
    vec3 position;
    vec2 parameter;
    flat uint code;
    flat uvec4 grid;
} gs[];

uniform mat4 faceMatrix[5];   // world -> clip per face: top, +t, -t, +b, -b
uniform vec3 eye;             // hemicube centre (patch centroid)
uniform vec3 normal;          // patch normal
uniform uint skipCode;        // the code under which the patch itself is drawn
uniform float planeEpsilon;   // distance below which a vertex counts as on the patch plane
uniform float nearPlane;
uniform vec4 clipPlane;       // extra half-space kept (mirror passes); (0,0,0,1) keeps everything

#ifndef HEMICUBE_KIND
#define HEMICUBE_KIND 0
#endif
flat out uint fragCode;
#if HEMICUBE_KIND != 0
flat out uvec2 fragGrid;  // first patch, nu | nv << 16
out vec2 fragParameter;
#endif
out float gl_ClipDistance[1];

void main() {
    const uint code = gs[0].code;
    if (code == skipCode) return;
    const float d0 = dot(gs[0].position - eye, normal);
    const float d1 = dot(gs[1].position - eye, normal);
    const float d2 = dot(gs[2].position - eye, normal);
    if (max(d0, max(d1, d2)) <= planeEpsilon) return;
    for (int f = 0; f < 5; ++f) {
        vec4 c[3];
        for (int k = 0; k < 3; ++k) c[k] = faceMatrix[f] * vec4(gs[k].position, 1.0);
        // Entirely outside one plane of the face frustum (x, y in [-w, w], w >= near): skip.
        if (c[0].x < -c[0].w && c[1].x < -c[1].w && c[2].x < -c[2].w) continue;
        if (c[0].x > c[0].w && c[1].x > c[1].w && c[2].x > c[2].w) continue;
        if (c[0].y < -c[0].w && c[1].y < -c[1].w && c[2].y < -c[2].w) continue;
        if (c[0].y > c[0].w && c[1].y > c[1].w && c[2].y > c[2].w) continue;
        if (c[0].w < nearPlane && c[1].w < nearPlane && c[2].w < nearPlane) continue;
        for (int k = 0; k < 3; ++k) {
            gl_Position = c[k];
            gl_ViewportIndex = f;
            gl_ClipDistance[0] = dot(clipPlane, vec4(gs[k].position, 1.0));
            fragCode = code;
#if HEMICUBE_KIND != 0
            fragGrid = uvec2(gs[0].grid.x, gs[0].grid.y | (gs[0].grid.z << 16));
            fragParameter = gs[k].parameter;
#endif
            EmitVertex();
        }
        EndPrimitive();
    }
}
