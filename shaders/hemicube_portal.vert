#version 450
// Mirror portal marking, vertex stage: one triangle covering the whole atlas.
void main() {
    const vec2 corner = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
    gl_Position = vec4(corner, 0.0, 1.0);
}
