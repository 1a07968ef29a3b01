// Progressive stills: averages this refinement step's frame into the running mean of the steps
// before it (kept in float) and writes the mean back into the frame, which is then read back. The
// frame arrives unrounded, so only the mean that is sent is rounded to 8 bits, never the steps
// averaged into it; each step is clamped to what an 8-bit frame can show, as a sent frame is.
#include "include/uniforms.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform image2D frame_image;
layout(binding = 1, rgba32f) uniform image2D mean_image;
layout(location = 0) uniform int step;  // 0: the mean starts at this frame

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, u.image_size.xy))) return;
    vec4 frame = clamp(imageLoad(frame_image, pixel), 0.0, 1.0);
    vec4 mean = step == 0 ? frame : mix(imageLoad(mean_image, pixel), frame, 1.0 / float(step + 1));
    imageStore(mean_image, pixel, mean);
    imageStore(frame_image, pixel, mean);
}
