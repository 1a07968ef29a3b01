// The region drawn: the volume's box cut down by half-spaces (the crop box's faces, the clip
// planes). Mirrors server/optics/include/penumbra/optics/region.hpp line for line. Camera rays
// clip by the first u.region_counts.x half-spaces; what carries light by the first
// u.region_counts.y, which is 0 when the cut tissue still casts shadows.
#include "include/ray.glsl"

const int REGION_CAMERA = 0;
const int REGION_LIGHT = 1;

int region_count_for(int user) {
    return user == REGION_CAMERA ? u.region_counts.x : u.region_counts.y;
}

// The interval `line` of origin + t * direction narrowed to where it lies deeper than `depth`
// inside each of the first `count` half-spaces (depth 0: in them; depth d: every point within d
// of it is in them too); x >= y when it lies in none of it.
vec2 clip_to_half_spaces(int count, vec3 origin, vec3 direction, vec2 line, float depth) {
    for (int i = 0; i < count; ++i) {
        vec4 h = u.region_half_spaces[i];
        float along = dot(h.xyz, direction);
        float at = dot(h.xyz, origin) + h.w - depth;
        if (along == 0.0) {
            // Parallel to the face: wholly inside or wholly outside.
            if (at < 0.0) line.y = line.x;
        } else if (along > 0.0) {
            line.x = max(line.x, -at / along);
        } else {
            line.y = min(line.y, -at / along);
        }
    }
    return line;
}

// Where the whole line crosses the region as `user` sees it, t of either sign (as
// intersect_line_box); x > y or x == y when it misses.
vec2 intersect_line_region(vec3 origin, vec3 direction, int user) {
    vec2 line = intersect_line_box(origin, direction);
    if (line.x > line.y) return line;
    return clip_to_half_spaces(region_count_for(user), origin, direction, line, 0.0);
}

// Entry and exit of a ray from `origin` (as intersect_box: x >= 0).
vec2 intersect_region(vec3 origin, vec3 direction, int user) {
    vec2 line = intersect_line_region(origin, direction, user);
    return vec2(max(0.0, line.x), line.y);
}

// How near a face camera rays clip by a sample's gradient feels the cut: a voxel.
float cut_face_reach() {
    return max(u.voxel_size.x, max(u.voxel_size.y, u.voxel_size.z));
}

// The gradient at `world` (of value `value` there) with what the cut removed taken as empty: within
// cut_face_reach() of a face camera rays clip by, its component along the face's normal becomes the
// central difference whose outer neighbour is empty, so a cut face is shaded as a surface facing
// out of the cut.
vec3 gradient_at_cut(vec3 world, vec3 gradient, float value) {
    float reach = cut_face_reach();
    for (int i = 0; i < u.region_counts.x; ++i) {
        vec4 h = u.region_half_spaces[i];
        if (dot(h.xyz, world) + h.w < reach) {
            float along = dot(gradient, h.xyz);
            gradient += h.xyz * ((value + reach * along) / (2.0 * reach) - along);
        }
    }
    return gradient;
}
