// The volume texture seen from a shader: known voxels of int16 and uint16 volumes, fetched with
// texelFetch in a compute shader and mapped with the texture's value_map as the ray caster does,
// come back as their exact real values (rescale applied).

#include "volume_texture.hpp"

#include <penumbra/gpu/context.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/volume/volume.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::render {
namespace {

constexpr const char* fetch_shader = R"(#version 450
layout(local_size_x = 1) in;
layout(binding = 0) uniform sampler3D volume_texture;
layout(std430, binding = 0) readonly buffer Coordinates { ivec4 coordinates[]; };
layout(std430, binding = 1) writeonly buffer Values { float values[]; };
uniform vec2 value_map;
void main() {
    const uint i = gl_GlobalInvocationID.x;
    values[i] = texelFetch(volume_texture, coordinates[i].xyz, 0).r * value_map.x + value_map.y;
}
)";

GLuint compile_fetch_program() {
    const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
    glShaderSource(shader, 1, &fetch_shader, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    EXPECT_TRUE(ok) << "the fetch shader does not compile";
    const GLuint program = glCreateProgram();
    glAttachShader(program, shader);
    glLinkProgram(program);
    glDeleteShader(shader);
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    EXPECT_TRUE(ok) << "the fetch shader does not link";
    return program;
}

// The real values of `voxels` as the GPU sees them: fetched, mapped to [0, 1] by value_map, then
// back to the volume's range in double.
std::vector<double> fetch(const volume::Volume& volume, const std::vector<glm::ivec4>& voxels) {
    auto texture = upload_volume(volume, 2048);
    EXPECT_TRUE(texture.ok()) << texture.error().to_string();
    if (!texture.ok()) {
        return {};
    }
    const GLuint program = compile_fetch_program();
    gpu::Buffer coordinates = gpu::create_buffer();
    glNamedBufferData(coordinates.name(),
                      static_cast<GLsizeiptr>(voxels.size() * sizeof(glm::ivec4)), voxels.data(),
                      GL_STATIC_DRAW);
    gpu::Buffer values = gpu::create_buffer();
    glNamedBufferData(values.name(), static_cast<GLsizeiptr>(voxels.size() * sizeof(float)),
                      nullptr, GL_DYNAMIC_READ);
    glUseProgram(program);
    glBindTextureUnit(0, texture->texture.name());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, coordinates.name());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, values.name());
    glUniform2f(glGetUniformLocation(program, "value_map"), texture->value_map.x,
                texture->value_map.y);
    glDispatchCompute(static_cast<GLuint>(voxels.size()), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> normalised(voxels.size());
    glGetNamedBufferSubData(values.name(), 0,
                            static_cast<GLsizeiptr>(normalised.size() * sizeof(float)),
                            normalised.data());
    glDeleteProgram(program);
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    std::vector<double> real;
    const double width = volume.range.max - volume.range.min;
    for (const float value : normalised) {
        real.push_back(volume.range.min + static_cast<double>(value) * width);
    }
    return real;
}

template <class T>
std::vector<std::byte> as_bytes(const std::vector<T>& values) {
    std::vector<std::byte> bytes(values.size() * sizeof(T));
    std::memcpy(bytes.data(), values.data(), bytes.size());
    return bytes;
}

// Every voxel is fetched; the mapped value, rounded to the nearest whole Hounsfield unit, is the
// voxel's exactly, and float32's rounding in the map stays far below half a unit.
void expect_exact(const volume::Volume& volume) {
    std::vector<glm::ivec4> voxels;
    for (std::uint32_t z = 0; z < volume.dims.z; ++z) {
        for (std::uint32_t y = 0; y < volume.dims.y; ++y) {
            for (std::uint32_t x = 0; x < volume.dims.x; ++x) {
                voxels.emplace_back(x, y, z, 0);
            }
        }
    }
    const std::vector<double> fetched = fetch(volume, voxels);
    ASSERT_EQ(fetched.size(), voxels.size());
    for (std::size_t i = 0; i < voxels.size(); ++i) {
        const auto& v = voxels[i];
        const double expected =
                volume.value(static_cast<std::uint32_t>(v.x), static_cast<std::uint32_t>(v.y),
                             static_cast<std::uint32_t>(v.z));
        EXPECT_EQ(std::round(fetched[i]), expected) << "voxel " << v.x << "," << v.y << "," << v.z;
        EXPECT_NEAR(fetched[i], expected, 0.05) << "voxel " << v.x << "," << v.y << "," << v.z;
    }
}

class VolumeTexture : public ::testing::Test {
protected:
    void SetUp() override {
        auto created = gpu::Context::create();
        ASSERT_TRUE(created.ok()) << created.error().to_string();
        context_.emplace(std::move(created.value()));
    }

    std::optional<gpu::Context> context_;
};

// A CT in int16 with the usual intercept: air, fat, water, bone and the extremes of int16,
// including -32768, which a signed-normalised texture could not tell from -32767.
TEST_F(VolumeTexture, Int16CtVoxelsAreExactInTheShader) {
    const std::vector<std::int16_t> stored{-32768, -32767, -1,   0,     1,     24,    1024, 1324,
                                           2024,   3000,   4095, 32766, 32767, -2000, 7,    8};
    auto ct = volume::make_volume("ct", {4, 2, 2}, glm::dvec3(1.0), volume::VoxelType::int16,
                                  as_bytes(stored), volume::Rescale{1.0, -1024.0});
    ASSERT_TRUE(ct.ok()) << ct.error().to_string();
    expect_exact(*ct);
}

TEST_F(VolumeTexture, Int16WithinAClinicalRangeIsExactInTheShader) {
    std::vector<std::int16_t> stored;
    for (int value = 0; value < 4096; value += 7) {
        stored.push_back(static_cast<std::int16_t>(value));
    }
    stored.resize(16 * 16 * 3, 4095);
    auto ct = volume::make_volume("ct", {16, 16, 3}, glm::dvec3(1.0), volume::VoxelType::int16,
                                  as_bytes(stored), volume::Rescale{1.0, -1024.0});
    ASSERT_TRUE(ct.ok()) << ct.error().to_string();
    expect_exact(*ct);
}

TEST_F(VolumeTexture, Uint16WithRescaleIsExactInTheShader) {
    const std::vector<std::uint16_t> stored{0, 1, 2, 1000, 4095, 65534, 65535, 12345};
    auto mr = volume::make_volume("mr", {2, 2, 2}, glm::dvec3(1.0), volume::VoxelType::uint16,
                                  as_bytes(stored), volume::Rescale{1.0, -1024.0});
    ASSERT_TRUE(mr.ok()) << mr.error().to_string();
    expect_exact(*mr);
}

}  // namespace
}  // namespace penumbra::render
