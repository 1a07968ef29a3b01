// Builder B: one dispatch fills every layer. Each invocation follows one light-buffer texel's
// ray from the light through all n slice planes, storing the transmittance that reaches each
// plane before attenuating it by that slice. Only the slices whose crossing lies in the box are
// sampled: outside it a slice passes the light unchanged, and the light view's corners see
// nothing of the volume at all. With empty-space skipping the ray leaps over runs of slabs that
// lie in empty bricks; it stops sampling where the light left is negligible. A large buffer is
// filled in tiles of texels starting at `texel_origin`, so that its build can be cancelled
// between them.
#include "include/uniforms.glsl"
#include "include/volume.glsl"
#include "include/transfer_function.glsl"
#include "include/compositing.glsl"
#include "include/light_slab.glsl"
#include "include/ray.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, r16f) uniform writeonly image2DArray light_layers;
layout(location = 0) uniform ivec2 texel_origin;

void store_light(ivec2 texel, int layer, float transmittance) {
    imageStore(light_layers, ivec3(texel, layer), vec4(transmittance));
}

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
    int count = int(u.light_slicing.z);
    int samples = int(u.light_buffer_info.y);
    // One slice of margin either side: sampled_slab_opacity decides at the region's faces.
    vec2 crossing = intersect_line_region(origin, ray, REGION_LIGHT);
    float origin_plane = dot(travel, origin);
    float first_plane = origin_plane + crossing.x * along_axis;
    float last_plane = origin_plane + crossing.y * along_axis;
    // Clamped before the conversion: a line that misses the box has no meaningful planes.
    bool hits = crossing.x <= crossing.y;
    float first_slice = (first_plane - u.light_slicing.x) / u.light_slicing.w - 0.5;
    float last_slice = (last_plane - u.light_slicing.x) / u.light_slicing.w - 0.5;
    int first = hits ? int(clamp(floor(first_slice), 0.0, float(count))) : count;
    // Slab n - 1 dims no layer: the last layer holds the light before it.
    int last = hits ? int(clamp(ceil(last_slice), -1.0, float(count - 2))) : -1;
    // Slab k spans t in centre(k) -+ path_length / 2 along the texel's line, one after another.
    float slab_t0 = (u.light_slicing.x - origin_plane) / along_axis;
#if EMPTY_SPACE_SKIPPING
    BrickWalk walk = start_brick_walk(origin, ray, crossing.x);
    float limit = slab_t0 + float(last + 1) * path_length;
#endif
    float transmittance = 1.0;
    int layer = 0;  // the first layer not written yet
    // One turn per slab that is sampled, or per run of empty slabs leapt over: a software
    // rasteriser runs a turn's whole body whichever branch its invocations take, so a slab is
    // only spared by not being a turn. The light stops where too little of it is left to matter.
    int k = first;
    while (k <= last && transmittance >= negligible_transmittance) {
        float start = slab_t0 + float(k) * path_length;
#if EMPTY_SPACE_SKIPPING
        float occupied = occupied_from(walk, start, limit);
        if (occupied >= start + path_length) {
            // The first slab that reaches into the occupied brick (rounding can only put it a
            // hair further, where its samples, half a step inside it, still lie before the brick).
            k = max(k + 1, int(floor((occupied - slab_t0) / path_length)));
            continue;
        }
#endif
        // The layers up to slice k receive the light as it is before slab k dims it. The layers
        // start cleared to 1: only light that something dimmed needs writing, which spares the
        // writes in front of the volume and where the light misses it.
        for (; layer <= k; ++layer) {
            if (transmittance < 1.0) store_light(texel, layer, transmittance);
        }
        // A slab within the crossing lies in every half-space the light meets: no test per point.
        int half_spaces = start >= crossing.x && start + path_length <= crossing.y
                                  ? 0
                                  : region_count_for(REGION_LIGHT);
        float alpha = sampled_slab_opacity(origin + (start + 0.5 * path_length) * ray, ray,
                                           path_length, samples, half_spaces);
        transmittance *= slab_transmittance_of(alpha);
        ++k;
    }
    for (; layer < count; ++layer) {
        if (transmittance < 1.0) store_light(texel, layer, transmittance);
    }
}
