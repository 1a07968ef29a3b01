// Ray caster as a compute shader writing one texel per pixel (row 0 = top of the image).
#include "raycast.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba8) uniform writeonly image2D frame_image;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, u.image_size.xy))) return;
    imageStore(frame_image, pixel, march(pixel));
}
