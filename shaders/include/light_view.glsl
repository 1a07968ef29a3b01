// The light's point of view; mirrors light_uv() and light_travel_direction() of server/optics.

// Paper eq. 9: light-buffer texture coordinates through the light's view-projection.
vec2 light_uv(vec3 world) {
    vec4 clip = u.light_view_projection * vec4(world, 1.0);
    return clip.xy / clip.w * 0.5 + 0.5;
}

// The direction light travels at `world`: L for a directional light, away from a point light.
vec3 light_travel_at(vec3 world) {
    return u.light_travel.w > 0.5 ? normalize(world - u.light_vector.xyz) : u.light_travel.xyz;
}
