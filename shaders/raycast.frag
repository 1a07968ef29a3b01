// Ray caster as a fragment shader over a full-screen triangle. Texel row r holds image row r
// (row 0 = top), the same layout the compute form writes, so readback needs no flip.
#include "raycast.glsl"

layout(location = 0) out vec4 frame_color;

void main() {
    frame_color = march(ivec2(gl_FragCoord.xy));
}
