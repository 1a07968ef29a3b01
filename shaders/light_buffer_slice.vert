// Builder A (the paper's): slice k's polygon seen from the light.
#include "include/uniforms.glsl"

layout(location = 0) in vec3 world_position;
out vec3 slice_world;

void main() {
    slice_world = world_position;
    gl_Position = u.light_view_projection * vec4(world_position, 1.0);
}
