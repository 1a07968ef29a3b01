// Builder B: one dispatch fills every layer. Each invocation follows one light-buffer texel's
// ray from the light through all n slice planes, storing the transmittance that reaches each
// plane before attenuating it by that slice. Only the slices whose crossing lies in the box are
// sampled: outside it a slice passes the light unchanged, and the light view's corners see
// nothing of the volume at all. A large buffer is filled in tiles of texels starting at
// `texel_origin`, so that its build can be cancelled between them.
#include "include/uniforms.glsl"
#include "include/volume.glsl"
#include "include/transfer_function.glsl"
#include "include/compositing.glsl"
#include "include/light_slab.glsl"
#include "include/ray.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, r16f) uniform writeonly image2DArray light_layers;
layout(location = 0) uniform ivec2 texel_origin;

void main() {
    int resolution = int(u.light_buffer_info.x);
    ivec2 texel = texel_origin + ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(texel, ivec2(resolution)))) return;
    vec2 ndc = (vec2(texel) + 0.5) / float(resolution) * 2.0 - 1.0;
    vec4 near_point = u.light_inverse_view_projection * vec4(ndc, -1.0, 1.0);
    vec4 far_point = u.light_inverse_view_projection * vec4(ndc, 1.0, 1.0);
    vec3 origin = near_point.xyz / near_point.w;
    vec3 ray = normalize(far_point.xyz / far_point.w - origin);
    vec3 travel = u.light_travel.xyz;
    float along_axis = dot(travel, ray);  // > 0: the light view looks along L
    float path_length = u.light_slicing.w / along_axis;
    float compensation = u.light_buffer_info.y;
    int count = int(u.light_slicing.z);
    int samples = int(u.light_buffer_info.z);
    // One slice of margin either side: slab_transmittance decides at the box's faces.
    vec2 crossing = intersect_line_box(origin, ray);
    float first_plane = dot(travel, origin) + crossing.x * along_axis;
    float last_plane = dot(travel, origin) + crossing.y * along_axis;
    // Clamped before the conversion: a line that misses the box has no meaningful planes.
    bool hits = crossing.x <= crossing.y;
    float first_slice = (first_plane - u.light_slicing.x) / u.light_slicing.w - 0.5;
    float last_slice = (last_plane - u.light_slicing.x) / u.light_slicing.w - 0.5;
    int first = hits ? int(clamp(floor(first_slice), -1.0, float(count))) : count;
    int last = hits ? int(clamp(ceil(last_slice), -1.0, float(count))) : -1;
    float transmittance = 1.0;
    // The layers start cleared to 1: only light that something dimmed needs writing, which spares
    // the writes in front of the volume and where the light misses it.
    for (int k = 0; k < count; ++k) {
        if (transmittance < 1.0) imageStore(light_layers, ivec3(texel, k), vec4(transmittance));
        if (k < first || k > last || transmittance <= 0.0) continue;
        float plane = u.light_slicing.x + (float(k) + 0.5) * u.light_slicing.w;
        vec3 p = origin + (plane - dot(travel, origin)) / along_axis * ray;
        transmittance *= slab_transmittance(p, ray, path_length, compensation, samples);
    }
}
