#version 450
// Viewer scene pass, fragment stage: writes every layer of the offscreen target at once.
//   0: patch id + 1 (R32UI; 0 = background)   1: radiance B / pi (flat or Gouraud)
//   2: emission E / pi                         3: diffuse reflectance   4: mirror reflectance
flat in uint vPatch;
in vec3 vCorner;

struct PatchData {
    vec4 radiosity;   // B (W/m^2), w unused
    vec4 emission;    // E
    vec4 reflectance; // rho rgb, s in w
};
layout(std430, binding = 0) readonly buffer Patches { PatchData patches[]; };

uniform bool gouraud;

layout(location = 0) out uint outId;
layout(location = 1) out vec4 outRadiance;
layout(location = 2) out vec4 outEmission;
layout(location = 3) out vec4 outReflectance;
layout(location = 4) out vec4 outSpecular;

const float kInvPi = 0.31830988618;

void main() {
    const PatchData p = patches[vPatch];
    // Radiosity leaves the front only: the back of a patch is black.
    const bool front = gl_FrontFacing;
    outId = vPatch + 1u;
    outRadiance = vec4(front ? (gouraud ? vCorner : p.radiosity.rgb) * kInvPi : vec3(0.0), 1.0);
    outEmission = vec4(front ? p.emission.rgb * kInvPi : vec3(0.0), 1.0);
    outReflectance = vec4(p.reflectance.rgb, 1.0);
    outSpecular = vec4(vec3(p.reflectance.w), 1.0);
}
