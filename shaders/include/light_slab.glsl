// What one light slice does to the light crossing it, shared by both light-buffer builders and by
// half-angle slicing: the TF opacity across the slab the slice stands for, corrected for the path
// length through it, and the paper's darkening compensation (1 + a)^c, never brightening past 1.

#include "include/empty_space.glsl"
#include "include/region.glsl"
#include "include/labels.glsl"
#include "include/preintegration.glsl"

bool inside_box(vec3 world) {
    vec3 p = box_coordinate(world);
    return all(greaterThanEqual(p, u.box_min.xyz)) && all(lessThanEqual(p, u.box_max.xyz));
}

// The slab's opacity from `samples` points spread evenly along the light's ray across it, each
// corrected for its share of the path. One point (the paper's slice) puts a surface anywhere in
// the slab at the slice plane, which shows as rings of the slice spacing on lit surfaces.
// The light meets what lies in the box and in the first `half_spaces` of the light's half-spaces
// (region_count_for(REGION_LIGHT), or 0 where the caller knows the slab lies in them all: finding
// the part it keeps costs as much as a tenth of a frame if every sample asks). In a slab a cut
// face crosses, the points spread over the part kept (one interval: the region is convex), so
// that the part dims the light by its length; a point tested in or out would count the whole
// slab or none of it, and light a cut face as if a slab of tissue were gone or still there.
// With PREINTEGRATION the slab is `samples` segments end to end, each classified by the values at
// its two ends (one fetch more than the points): a thin opaque value range that lies between two
// points still dims the light, as it does on the camera's rays, and a slab's back end is the next
// slab's front, so that no value range falls between two slabs either.
float sampled_slab_opacity(vec3 centre, vec3 ray, float path_length, int samples,
                           int half_spaces) {
    vec3 start = centre - 0.5 * path_length * ray;
    vec2 kept = clip_to_half_spaces(half_spaces, start, ray, vec2(0.0, path_length), 0.0);
    if (kept.x >= kept.y) return 0.0;
    float step = (kept.y - kept.x) / float(samples);
    float transmittance = 1.0;
#if PREINTEGRATION
    float front = sample_value(start + kept.x * ray);
    for (int j = 0; j < samples; ++j) {
        float back = sample_value(start + (kept.x + float(j + 1) * step) * ray);
        vec3 p = start + (kept.x + (float(j) + 0.5) * step) * ray;
        if (inside_box(p)) {
            transmittance *=
                    1.0 - sample_opacity(in_label(classify_segment(front, back), p).a, step);
        }
        front = back;
    }
#else
    for (int j = 0; j < samples; ++j) {
        vec3 p = start + (kept.x + (float(j) + 0.5) * step) * ray;
        if (inside_box(p)) {
            transmittance *= 1.0 - sample_opacity(in_label(classify(sample_value(p)), p).a, step);
        }
    }
#endif
    return 1.0 - transmittance;
}

// As sampled_slab_opacity, for a slab sampled on its own (not as one of a march's run of slabs,
// which can walk the bricks once: BrickWalk).
float slab_opacity(vec3 centre, vec3 ray, float path_length, int samples) {
    vec3 start = centre - 0.5 * path_length * ray;
    // A slab that the cut removes whole (as the light sees the cut) lets all light through: one
    // look, as at an empty brick, so that the light pass takes no samples where the cut left
    // nothing (the work estimate counts the bricks it leaves out as empty).
    vec2 kept = clip_to_half_spaces(region_count_for(REGION_LIGHT), start, ray,
                                    vec2(0.0, path_length), 0.0);
    if (kept.x >= kept.y) return 0.0;
    // A slab the cut leaves whole lies in every half-space (both its ends do, and they are convex).
    int half_spaces = kept.x <= 0.0 && kept.y >= path_length ? 0 : region_count_for(REGION_LIGHT);
#if EMPTY_SPACE_SKIPPING
    // A slab is a voxel or two thick: one look at the brick where it starts decides for the
    // whole slab, where a look per point would cost about as much as the points themselves.
    if (inside_box(start) && empty_run(start, ray) >= path_length) return 0.0;
#endif
    return sampled_slab_opacity(centre, ray, path_length, samples, half_spaces);
}

// The light a slab of opacity `alpha` lets through.
float slab_transmittance_of(float alpha) {
    // An opaque slice stays opaque: 0 * (1 + a)^c overflows to 0 * inf = NaN for large c.
    if (alpha >= 1.0) return 0.0;
    return min(1.0, (1.0 - alpha) * pow(1.0 + alpha, settings.light_buffer_compensation));
}

float slab_transmittance(vec3 centre, vec3 ray, float path_length, int samples) {
    return slab_transmittance_of(slab_opacity(centre, ray, path_length, samples));
}
