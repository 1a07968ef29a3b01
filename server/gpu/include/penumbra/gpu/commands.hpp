#pragma once

// What passes do with the objects of objects.hpp: fill and read them, bind them, run programs over
// them and draw into framebuffers. Each helper sets the state it depends on (pixel alignment, the
// program in use) instead of trusting what an earlier call left behind.

#include <penumbra/gpu/objects.hpp>

#include <array>
#include <cstddef>
#include <span>

namespace penumbra::gpu {

// --- Content. Pixels are rows packed without padding, in GL's order (bottom row first).

// How `texture` is sampled: `filter` when minifying and magnifying, `wrap` on every axis.
void set_sampling(const Texture& texture, GLenum filter, GLenum wrap);

// Replaces level 0 of a 1D or 3D texture of these dimensions.
void upload_1d(const Texture& texture, int width, GLenum format, GLenum type, const void* pixels);
void upload_3d(const Texture& texture, int width, int height, int depth, GLenum format, GLenum type,
               const void* pixels);

// Replaces the first bytes of `buffer` (made by create_storage_buffer).
void upload(const Buffer& buffer, std::span<const std::byte> bytes);

// Level 0 of `texture`, all of it, into `out`, which holds exactly that much.
void read_texture(const Texture& texture, GLenum format, GLenum type, std::span<std::byte> out);

// One width x height layer of an array texture's level 0 into `out`.
void read_texture_layer(const Texture& texture, int layer, int width, int height, GLenum format,
                        GLenum type, std::span<std::byte> out);

// Sets every texel of level 0 (every layer) to `value`, converted to the texture's format.
void clear(const Texture& texture, std::array<float, 4> value);

// Copies the width x height 2D texture `from` into layer `layer` of the array texture `to`.
void copy_into_layer(const Texture& from, const Texture& to, int layer, int width, int height);

// --- Binding.

void bind_texture(GLuint unit, const Texture& texture);  // for samplers

// Level 0 of `texture`, every layer of it, as image unit `unit` with the shader's `format`.
void bind_image(GLuint unit, const Texture& texture, GLenum access, GLenum format);

void bind_uniform_buffer(GLuint binding, const Buffer& buffer);
void bind_storage_buffer(GLuint binding, const Buffer& buffer);

void set_uniform(const Program& program, GLint location, int value);
void set_uniform(const Program& program, GLint location, int x, int y);
void set_uniform(const Program& program, GLint location, float x, float y);

// --- Compute.

struct Groups {
    GLuint x = 1;
    GLuint y = 1;
    GLuint z = 1;
};

// The work groups of `side` invocations along each axis that cover x by y by z invocations.
Groups groups_covering(int side, int x, int y = 1, int z = 1);

// Runs the compute `program` over `groups`, then waits, as glMemoryBarrier(`barriers`) says, until
// what it wrote is visible to the commands that read it next.
void dispatch(const Program& program, Groups groups, GLbitfield barriers);

void memory_barrier(GLbitfield barriers);

// --- Drawing.

// How what a draw writes combines with the framebuffer: `none` replaces it; `under` composites
// front to back, `over` back to front (premultiplied colour); `multiply` scales it by the colour
// drawn.
enum class Blend { none, under, over, multiply };

// Draws that follow go to `framebuffer` over width x height, without depth test or face culling,
// blended as `blend`.
void draw_into(const Framebuffer& framebuffer, int width, int height, Blend blend);

// Draws (and clears) reach only this rectangle until end_drawing().
void set_scissor(int x, int y, int width, int height);

// Triangles [first, first + count) of `vertices` with `program`.
void draw_triangles(const Program& program, const VertexArray& vertices, int first, int count);

// Back to the default framebuffer, unblended, without a scissor rectangle.
void end_drawing();

void clear(const Framebuffer& framebuffer, std::array<float, 4> colour);

[[nodiscard]] bool is_complete(const Framebuffer& framebuffer);

// Attribute 0 of `vertices` reads `components` floats per vertex from `buffer`.
void attach_positions(const VertexArray& vertices, const Buffer& buffer, int components);

// --- Synchronisation.

// Waits until every command issued so far has finished (for wall-clock timing and cancellation).
void finish();

// The oldest error GL has recorded since the last call (GL_NO_ERROR when none), which it forgets.
GLenum take_error();

}  // namespace penumbra::gpu
