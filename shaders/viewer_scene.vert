#version 450
// Viewer scene pass, vertex stage: patch triangles with their corner radiosity (Gouraud).
layout(location = 0) in vec3 position;
layout(location = 1) in uint patchId;
layout(location = 2) in vec3 cornerRadiosity;

uniform mat4 viewProjection;
uniform mat4 model;          // identity, or a mirror reflection for the reflected pass
uniform vec4 clipPlane;      // world half-space kept (reflected pass); (0, 0, 0, 1) keeps all

flat out uint vPatch;
out vec3 vCorner;

void main() {
    const vec4 world = model * vec4(position, 1.0);
    gl_Position = viewProjection * world;
    gl_ClipDistance[0] = dot(clipPlane, vec4(position, 1.0));
    vPatch = patchId;
    vCorner = cornerRadiosity;
}
