// Ray caster as a compute shader writing one texel per pixel (row 0 = top of the image).
//   CHUNKED 0|1: march only samples [first_sample, first_sample + sample_budget) of the rays of
//   the tile at `tile_origin` and keep the running sum in `accumulation`; resolve.comp finishes
//   the frame. GL implementations that cap the loop iterations of one invocation (llvmpipe: 65535)
//   need it for long rays, and a long frame is cut this way so that it can be cancelled.
#include "raycast.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

#if CHUNKED
layout(binding = 1, rgba32f) uniform image2D accumulation;
layout(location = 0) uniform int first_sample;
layout(location = 1) uniform int sample_budget;
layout(location = 2) uniform ivec2 tile_origin;

void main() {
    ivec2 pixel = tile_origin + ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, u.image_size.xy))) return;
    vec4 accumulated = first_sample == 0 ? vec4(0.0) : imageLoad(accumulation, pixel);
    if (accumulated.a < settings.early_termination) {
        march_range(pixel, first_sample, sample_budget, accumulated);
    }
    imageStore(accumulation, pixel, accumulated);
}
#else
layout(binding = 0, rgba32f) uniform writeonly image2D frame_image;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, u.image_size.xy))) return;
    imageStore(frame_image, pixel, march(pixel));
}
#endif
