// A label map drawn inside the volume (scene/labels.hpp); mirrors server/optics labels.hpp.
// LABELS 0|1. The label map keeps its own grid: a sample's label is the voxel nearest to it in the
// map's own index space (u.world_to_label), fetched, never filtered, so ids never mix at a
// boundary. The transfer function gives the opacity; the label scales it (0 where hidden, for
// camera rays and for everything that carries light alike) and tints the colour.
#ifndef LABELS
#define LABELS 0
#endif

#if LABELS
layout(binding = 7) uniform usampler3D label_indices;
// Per index: rgb the label's colour, a its opacity scale. Index 0 is the background (and
// everything outside the map): the scan as it is.
layout(binding = 8) uniform sampler1D label_styles;

int label_index(vec3 world) {
    ivec3 voxel = ivec3(floor((u.world_to_label * vec4(world, 1.0)).xyz + 0.5));
    if (any(lessThan(voxel, ivec3(0))) ||
        any(greaterThanEqual(voxel, textureSize(label_indices, 0)))) {
        return 0;
    }
    return int(texelFetch(label_indices, voxel, 0).r);
}

// What the transfer function classified at `world`, in the label there. A transparent sample
// stays transparent: no fetch.
vec4 in_label(vec4 classified, vec3 world) {
    if (classified.a <= 0.0) return classified;
    int index = label_index(world);
    vec4 style = texelFetch(label_styles, index, 0);
    float weight = index == 0 ? 0.0 : u.labels.x;
    return vec4(mix(classified.rgb, style.rgb, weight), classified.a * style.a);
}
#else
vec4 in_label(vec4 classified, vec3 world) {
    return classified;
}
#endif
