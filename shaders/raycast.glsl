// THE march loop: one source for every ray-cast mode; effects are compiled in or out by defines.
//
// Defines (injected by the renderer; see shaders/README.md):
//   SHADOWS      SHADOWS_NONE | SHADOWS_LIGHT_BUFFER | SHADOWS_RAYS
//   SCATTERING   SCATTERING_NONE | SCATTERING_SHELL | SCATTERING_CONE (with the light buffer)
//   PHONG        0|1  Blinn–Phong shading from central-difference gradients
//   EXTINCTION   0|1  extinction compositing (paper eq. 6) instead of corrected alpha
//   RECONSTRUCTION SETTINGS_RECONSTRUCTION_TRILINEAR | _TRICUBIC  how volume samples are filtered
//   POINT_LIGHT  0|1  the light is a point at light_vector rather than a direction
//   EMPTY_SPACE_SKIPPING 0|1  leap over bricks the transfer function leaves transparent
//   GRADIENT_TEXTURE 0|1  gradients from the precomputed texture instead of central differences
//   LABELS 0|1  a label map scales and tints what the transfer function classifies (labels.glsl)
//   PREINTEGRATION 0|1  each sample stands for the segment from the sample before it, classified
//                       by both values through the pre-integration table

#define SHADOWS_NONE 0
#define SHADOWS_LIGHT_BUFFER 1
#define SHADOWS_RAYS 2
#define SCATTERING_NONE 0
#define SCATTERING_SHELL 1
#define SCATTERING_CONE 2

#include "include/uniforms.glsl"
#include "include/ray.glsl"
#include "include/region.glsl"
#include "include/volume.glsl"
#include "include/transfer_function.glsl"
#include "include/labels.glsl"
#include "include/preintegration.glsl"
#include "include/empty_space.glsl"
#include "include/gradient.glsl"
#include "include/compositing.glsl"
#include "include/shading.glsl"
#if SHADOWS == SHADOWS_LIGHT_BUFFER
#include "include/light_buffer.glsl"
#include "include/scattering.glsl"
#elif SHADOWS == SHADOWS_RAYS
#include "include/shadow_ray.glsl"
#endif

// The fraction of the light that reaches `position` (1 without shadows); the stretch a local
// lookup marches toward the light is tested against the first `light_half_spaces` of the light's
// half-spaces.
float light_reaching(vec3 position, vec3 to_eye, int light_half_spaces) {
#if SHADOWS == SHADOWS_LIGHT_BUFFER && SCATTERING == SCATTERING_SHELL
    return shell_transmittance(position, light_half_spaces);
#elif SHADOWS == SHADOWS_LIGHT_BUFFER && SCATTERING == SCATTERING_CONE
    return cone_transmittance(position, to_eye, light_half_spaces);
#elif SHADOWS == SHADOWS_LIGHT_BUFFER
    return light_at_sample(position, light_half_spaces);
#elif SHADOWS == SHADOWS_RAYS
    return shadow_ray_transmittance(position);
#else
    return 1.0;
#endif
}

// A ray's march through the box: equal steps no longer than the sample distance, each sampled at
// the same fraction of the step: the midpoint, or the pixel's jittered offset (ray_start_offset).
struct RayMarch {
    vec3 origin;
    vec3 direction;
    float start;  // where the ray enters the region drawn
    float step_length;
    float offset;
#if EMPTY_SPACE_SKIPPING
    // Up to this distance along the ray the bricks are known to be occupied: samples before it
    // need no look at the grid. A sample just past a face by rounding is looked at again, which
    // can only keep a sample, never drop one.
    float occupied_until;
#if LABELS
    // Whether every sample of that stretch lies in one label (the brick classification found its
    // brick to be of one), whose tint is then known: its samples fetch no label.
    bool one_label;
    LabelTint one_label_tint;
#endif
#endif
#if LABELS
    // The ray in the label map's index space, where a sample's label is looked up.
    vec3 label_origin;
    vec3 label_direction;
#endif
#if PREINTEGRATION
    float front;  // the value at the sample before the next one, the front of its segment
#endif
};

// A sample `t` along the ray, classified as `classified` by the transfer function, in its label.
vec4 labelled(RayMarch march, vec4 classified, float t) {
#if LABELS
    if (classified.a <= 0.0) return classified;
#if EMPTY_SPACE_SKIPPING
    if (march.one_label) return tinted(classified, march.one_label_tint);
#endif
    return tinted(classified,
                  label_tint(label_index_at(march.label_origin + t * march.label_direction)));
#else
    return classified;
#endif
}

vec3 march_position(RayMarch march, int i) {
    return march.origin + (march.start + (float(i) + march.offset) * march.step_length) *
                                  march.direction;
}

#if PREINTEGRATION
// The front of sample i's segment: the sample before it, or for the first sample the point where
// the ray enters the box. Not the first sample itself (its segment would then count as a plain
// sample): a surface right at the box face would lose what lies between the face and the first
// sample, and the entry point is one fetch per ray. The same for every chunk of a ray.
float front_value(RayMarch march, int i) {
    if (i <= 0) return sample_value(march.origin + march.start * march.direction);
    return sample_value(march_position(march, i - 1));
}
#endif

#if PREINTEGRATION
// How far before sample i its segment is lit and shaded: at the segment's middle, half a step
// before. The first segment starts where the ray enters the region (front_value) and stands, as
// every segment does, for a whole step: the one the first sample stands for without
// pre-integration, which it is lit at as well. Lit half a step before, on the region's face, a
// whole step of material would be lit as if it lay before a cut face, where the light is
// brightest.
float lit_before(RayMarch march, int i) {
    return i == 0 ? 0.0 : 0.5 * march.step_length;
}
#endif

// Sample i classified, or false where it lies in an empty brick: `i` then moves to the last
// sample in that brick, so that the march's next step leaves it.
//
// With PREINTEGRATION the sample's segment from the sample before it is classified. A segment
// with both ends in one empty brick is exactly transparent to the table's integral, its values
// lying between two of the brick's (up to the table's filter, one cell of the table wide); a
// segment that leaves an occupied brick for an empty one, or leaves an empty one, may not be: so
// the first sample of an empty brick is still classified as a segment, and the leap fetches the
// value of the last sample it passes, the front of the first segment after it.
bool classify_sample(inout RayMarch march, inout int i, out vec3 position, out vec4 classified) {
    float t = march.start + (float(i) + march.offset) * march.step_length;
    position = march.origin + t * march.direction;
    classified = vec4(0.0);
#if EMPTY_SPACE_SKIPPING
    if (t >= march.occupied_until) {
        ivec3 brick = brick_of(position);
        float run = distance_out_of_brick(position, march.direction, brick);
        uint occupancy = brick_occupancy_of(brick);
        if (occupancy == 0u) {
            int last_in_brick = max(i + 1, i + int(ceil(run / march.step_length))) - 1;
#if PREINTEGRATION
            float back = sample_value(position);
            classified = labelled(march, classify_segment(march.front, back), t);
            march.front = last_in_brick > i ? sample_value(march_position(march, last_in_brick))
                                            : back;
            position -= lit_before(march, i) * march.direction;  // as below
            i = last_in_brick;
            return true;
#else
            i = last_in_brick;
            return false;
#endif
        }
        march.occupied_until = t + run;
#if LABELS
        march.one_label = occupancy >= 2u;
        if (march.one_label) march.one_label_tint = label_tint(int(occupancy) - 2);
#endif
    }
#endif
#if PREINTEGRATION
    float back = sample_value(position);
    classified = labelled(march, classify_segment(march.front, back), t);
    march.front = back;
    // The segment is lit and shaded at its middle, where its material is on average: lit at its
    // back, a surface would be lit half a step inside itself and darken under shadows.
    position -= lit_before(march, i) * march.direction;
#else
    classified = labelled(march, classify(sample_value(position)), t);
#endif
    return true;
}

// Front-to-back emission–absorption of samples [first, first + budget) of the ray of `pixel`,
// composited into `accumulated` (premultiplied).
//
// Where samples are shaded, two loops: the inner one fetches and classifies samples until one is
// visible, the outer one shades and composites it. A SIMD machine (a GPU's warp, a software
// rasteriser's vector of pixels) runs a loop turn's whole body while any of its rays needs it:
// shading in the turn that fetches would cost every transparent sample a gradient and a light
// lookup as soon as one ray beside it met something.
void march_range(ivec2 pixel, int first, int budget, inout vec4 accumulated) {
    RayMarch march;
    march.origin = u.eye.xyz;
    march.direction = pixel_ray_direction(pixel);
    vec2 hit = intersect_region(march.origin, march.direction, REGION_CAMERA);
    float length_inside = hit.y - hit.x;
    if (length_inside <= 0.0) return;
    int count = int(max(1.0, ceil(length_inside / settings.sample_distance)));
    march.start = hit.x;
    march.step_length = length_inside / float(count);
    march.offset = ray_start_offset(pixel);
#if EMPTY_SPACE_SKIPPING
    march.occupied_until = -1.0;
#if LABELS
    march.one_label = false;
    march.one_label_tint = LabelTint(vec4(1.0), 0.0);
#endif
#endif
#if LABELS
    march.label_origin = label_coordinate(march.origin);
    march.label_direction = mat3(u.world_to_label) * march.direction;
#endif
#if PREINTEGRATION
    march.front = front_value(march, first);
#endif
    int last = min(count, first + budget);
    vec3 position;
    vec4 classified;
#if PHONG || SHADOWS != SHADOWS_NONE
    // Where along the ray a sample lies deeper in the light's half-spaces than a local lookup's
    // stretch toward the light is long (u.light_buffer_info.z): its stretch lies in them too, and
    // its points need no test of them. Under a cut that is almost every sample.
    vec2 light_deep = clip_to_half_spaces(region_count_for(REGION_LIGHT), march.origin,
                                          march.direction, vec2(-3.0e38, 3.0e38),
                                          u.light_buffer_info.z);
#if PHONG
    // Likewise where a sample lies deeper than cut_face_reach() in every face camera rays clip by:
    // its gradient is the material's own, and it pays nothing for the cut.
    vec2 face_deep = clip_to_half_spaces(u.region_counts.x, march.origin, march.direction,
                                         vec2(-3.0e38, 3.0e38), cut_face_reach());
#endif
    int i = first;
    while (i < last) {
        for (; i < last; ++i) {
            if (classify_sample(march, i, position, classified) && classified.a > 0.0) break;
        }
        if (i >= last) break;
        vec2 terms = vec2(1.0, 0.0);
        float t = dot(position - march.origin, march.direction);
#if PHONG
        vec3 gradient = sample_gradient(position);
        if (t < face_deep.x || t > face_deep.y) {
            gradient = gradient_at_cut(position, gradient, sample_value(position));
        }
        vec3 normal = normal_from_gradient(gradient);
        terms = blinn_phong(normal, direction_to_light(position), -march.direction);
#endif
        int light_half_spaces =
                t >= light_deep.x && t <= light_deep.y ? 0 : region_count_for(REGION_LIGHT);
        vec3 color = shade(classified.rgb, terms,
                           light_reaching(position, -march.direction, light_half_spaces));
        composite_front_to_back(accumulated, color,
                                sample_opacity(classified.a, march.step_length));
        if (accumulated.a >= settings.early_termination) break;
        ++i;
    }
#else
    for (int i = first; i < last; ++i) {
        if (!classify_sample(march, i, position, classified) || classified.a <= 0.0) continue;
        composite_front_to_back(accumulated, classified.rgb,
                                sample_opacity(classified.a, march.step_length));
        if (accumulated.a >= settings.early_termination) break;
    }
#endif
}

// The whole ray, composited over the background.
vec4 march(ivec2 pixel) {
    vec4 accumulated = vec4(0.0);
    march_range(pixel, 0, 0x7fffffff, accumulated);
    return vec4(accumulated.rgb + (1.0 - accumulated.a) * u.background.rgb, 1.0);
}
