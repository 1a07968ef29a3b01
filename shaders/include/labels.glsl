// A label map drawn inside the volume (scene/labels.hpp); mirrors server/optics labels.hpp.
// LABELS 0|1. The label map keeps its own grid: a sample's label is the voxel nearest to it in the
// map's own index space (u.world_to_label), fetched, never filtered, so ids never mix at a
// boundary. The transfer function gives the opacity; the label scales it (0 where hidden, for
// camera rays and for everything that carries light alike) and tints the colour.
#ifndef LABELS
#define LABELS 0
#endif

#if LABELS
#include "include/label_styles.glsl"

layout(binding = 7) uniform usampler3D label_indices;

// `world` in the map's voxel index space (a ray's points there lie on a line as well).
vec3 label_coordinate(vec3 world) {
    return (u.world_to_label * vec4(world, 1.0)).xyz;
}

// The label index of the map's voxel nearest to `coordinate` (label_coordinate), 0 outside it.
int label_index_at(vec3 coordinate) {
    ivec3 voxel = ivec3(floor(coordinate + 0.5));
    if (any(lessThan(voxel, ivec3(0))) ||
        any(greaterThanEqual(voxel, textureSize(label_indices, 0)))) {
        return 0;
    }
    return int(texelFetch(label_indices, voxel, 0).r);
}

// What a label does to a classified sample: its style, and how much its colour replaces the
// transfer function's (none for the background).
struct LabelTint {
    vec4 style;
    float weight;
};

LabelTint label_tint(int index) {
    return LabelTint(label_style(index), index == 0 ? 0.0 : u.labels.x);
}

vec4 tinted(vec4 classified, LabelTint tint) {
    return vec4(mix(classified.rgb, tint.style.rgb, tint.weight), classified.a * tint.style.a);
}

// What the transfer function classified at `world`, in the label there. A transparent sample
// stays transparent: no fetch.
vec4 in_label(vec4 classified, vec3 world) {
    if (classified.a <= 0.0) return classified;
    return tinted(classified, label_tint(label_index_at(label_coordinate(world))));
}
#else
vec4 in_label(vec4 classified, vec3 world) {
    return classified;
}
#endif
