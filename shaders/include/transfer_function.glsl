// Classification: the baked TF table (server/scene transfer_function bake()) as a 1D texture,
// sampled with linear filtering and clamped to its ends.
layout(binding = 1) uniform sampler1D transfer_function_texture;

vec4 classify(float normalized_value) {
    return texture(transfer_function_texture, clamp(normalized_value, 0.0, 1.0));
}
