#version 450
// Viewer scene pass, fragment stage: writes every layer of the offscreen target at once.
//   0: patch id + 1 (R32UI; 0 = background)   1: radiance B / pi (flat or Gouraud)
//   2: emission E / pi                         3: diffuse reflectance   4: mirror reflectance
//   5: level ids: id + 1 of front faces, 0 for back faces (the mirror passes follow front faces only)
// A mirror pass maps its outputs to layers 1 and 5 only (glDrawBuffers) and skips the patches of the
// mirror plane it reflects in: they lie on its clip plane, and a mirror does not see itself.
flat in uint vPatch;
in vec3 vCorner;

struct PatchData {
    vec4 radiosity;   // B (W/m^2), w unused
    vec4 emission;    // E
    vec4 reflectance; // rho rgb, s in w
};
layout(std430, binding = 0) readonly buffer Patches { PatchData patches[]; };
layout(std430, binding = 1) readonly buffer MirrorGroups { uint groupOfPatch[]; };

uniform bool gouraud;
uniform uint skipGroup;  // mirror group + 1 of the reflected pass, 0 for the direct view

layout(location = 0) out uint outId;
layout(location = 1) out vec4 outRadiance;
layout(location = 2) out vec4 outEmission;
layout(location = 3) out vec4 outReflectance;
layout(location = 4) out vec4 outSpecular;
layout(location = 5) out uint outLevelId;

const float kInvPi = 0.31830988618;

void main() {
    if (skipGroup != 0u && groupOfPatch[vPatch] == skipGroup) discard;
    const PatchData p = patches[vPatch];
    // Radiosity leaves the front only: the back of a patch is black.
    const bool front = gl_FrontFacing;
    outId = vPatch + 1u;
    outRadiance = vec4(front ? (gouraud ? vCorner : p.radiosity.rgb) * kInvPi : vec3(0.0), 1.0);
    outEmission = vec4(front ? p.emission.rgb * kInvPi : vec3(0.0), 1.0);
    outReflectance = vec4(p.reflectance.rgb, 1.0);
    outSpecular = vec4(vec3(p.reflectance.w), 1.0);
    outLevelId = front ? vPatch + 1u : 0u;
}
