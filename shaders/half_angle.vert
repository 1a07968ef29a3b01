// Half-angle slicing (Kniss et al. 2002): one slice polygon, seen from the camera (eye pass) or
// from the light (light pass, HALF_ANGLE_LIGHT_PASS = 1).
#include "include/uniforms.glsl"

layout(location = 0) in vec3 world_position;
out vec3 slice_world;

void main() {
    slice_world = world_position;
#if HALF_ANGLE_LIGHT_PASS
    gl_Position = u.light_view_projection * vec4(world_position, 1.0);
#else
    gl_Position = u.camera_view_projection * vec4(world_position, 1.0);
#endif
}
