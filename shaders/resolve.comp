// The last step of passes that accumulate in float (half-angle slicing's eye buffer, the chunked
// ray caster): premultiplied colour over the background, into the float frame (rows top to
// bottom).
#include "include/uniforms.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D eye_buffer;
layout(binding = 0, rgba32f) uniform writeonly image2D frame_image;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, u.image_size.xy))) return;
    vec4 eye = texelFetch(eye_buffer, pixel, 0);
    imageStore(frame_image, pixel, vec4(eye.rgb + (1.0 - eye.a) * u.background.rgb, 1.0));
}
