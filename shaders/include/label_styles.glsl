// The style table of the labels a frame draws (render::LabelTexture, from optics::LabelStyleTable):
// per label index, rgb the label's colour and a its opacity scale, 0 where it is hidden. Index 0
// is the background (and everything outside the map): the scan as it is. Read by the march
// (labels.glsl) and by the brick classification (brick_classify.comp).
layout(binding = 8) uniform sampler1D label_styles;

vec4 label_style(int index) {
    return texelFetch(label_styles, index, 0);
}
