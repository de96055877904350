#version 450
// Stage view `simulation`, arrows: the correction one step of the simulation made to
// each master-hair vertex in the frame's last substep (the kernel's probe,
// shaders/simulate.comp), as a line list, one instance per master hair and two
// vertices per strand vertex: from the vertex less the correction magnified
// frame.drawing.arrow_scale times (dark) to the vertex (bright magenta, a colour the displacement
// scale does not use).
#include "common.glsl"

layout(set = SET_FRAME, binding = B_PROBE, std430) readonly buffer Probe {
    vec4 arrows[];
};

layout(location = 0) out vec3 v_colour;

void main() {
    uint strand = uint(gl_InstanceIndex);
    uint vertex = uint(gl_VertexIndex) / 2u;
    bool head = (gl_VertexIndex & 1) == 1;
    vec3 p = strand_vertex(strand, vertex);
    vec3 d = arrows[strand * frame.strands.vertices_per_strand + vertex].xyz * frame.drawing.arrow_scale;
    gl_Position = frame.camera.view_proj * vec4(head ? p : p - d, 1.0);
    v_colour = head ? vec3(1.0, 0.2, 1.0) : vec3(0.12, 0.0, 0.12);
}
