#version 450
// Fur pass, vertex stage: pass-through. Each mesh vertex is a master hair; the index
// buffer's triangles become 3-point patches.

layout(location = 0) out uint v_hair;

void main() {
    v_hair = uint(gl_VertexIndex);
}
