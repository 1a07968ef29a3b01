// The generated Settings block seen from a shader: every setting of a frame in scene::kSettings,
// set to a value of its own, reads back in GLSL under its name with that value (each component of
// a vector or a size), at the offset the C++ side writes it to. A row the declaration or the buffer
// missed, a swapped pair or a std140 offset the driver lays out differently fails here.

#include "settings_block.hpp"

#include <penumbra/gpu/context.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/gpu/shader_library.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <unistd.h>

namespace penumbra::render {
namespace {

// The rows every frame carries, straight from the table (not through settings_members()).
std::vector<const scene::Setting*> frame_rows() {
    std::vector<const scene::Setting*> rows;
    for (const scene::Setting* row : scene::kSettings) {
        if (row->in_frame()) {
            rows.push_back(row);
        }
    }
    return rows;
}

std::size_t components_of(const scene::Setting& row) {
    switch (row.kind) {
        case scene::SettingKind::vector:
            return 3;
        case scene::SettingKind::size:
            return 2;
        case scene::SettingKind::number:
        case scene::SettingKind::whole:
        case scene::SettingKind::boolean:
        case scene::SettingKind::choice:
            return 1;
    }
    return 1;
}

// Each component of each row at its own fraction of its range, so that no two numbers share a
// value and a member read from another's place shows; a choice takes its last name, a boolean
// true, a size its range's fractions.
scene::FrameRequest distinctive_request(const std::vector<const scene::Setting*>& rows) {
    scene::State state;
    std::size_t component = 0;
    std::size_t components = 0;
    for (const scene::Setting* row : rows) {
        components += components_of(*row);
    }
    for (const scene::Setting* row : rows) {
        scene::SettingValue value(0.0);
        for (std::size_t i = 0; i < components_of(*row); ++i, ++component) {
            const double fraction =
                    static_cast<double>(component + 1) / static_cast<double>(components + 1);
            const double max = row->max_under(scene::Limits{});
            double v = row->min + (max - row->min) * fraction;
            if (row->kind != scene::SettingKind::number &&
                row->kind != scene::SettingKind::vector) {
                v = row->kind == scene::SettingKind::size ? std::round(v) : max;
            }
            value[static_cast<int>(i)] = v;
        }
        row->write(state, value);
    }
    return state.frame;
}

class SettingsBlockTest : public ::testing::Test {
protected:
    void SetUp() override {
        root_ = std::filesystem::temp_directory_path() /
                ("penumbra_settings_block_" + std::to_string(::getpid()));
        std::filesystem::create_directories(root_);
    }

    void TearDown() override { std::filesystem::remove_all(root_); }

    std::filesystem::path root_;
};

TEST(SettingsMemberName, IsThePathWithoutSettingsAndWithUnderscores) {
    EXPECT_EQ(settings_member_name("settings/light_buffer/compensation"),
              "light_buffer_compensation");
    EXPECT_EQ(settings_member_name("settings/sample_distance"), "sample_distance");
    EXPECT_EQ(settings_member_name("camera/fov"), "camera_fov");
}

// A choice reaches GLSL as the index of its name, with a define for each name in the enum's order.
TEST(SettingsBlockGlsl, NamesEachChoiceByADefine) {
    const std::string glsl = settings_block_glsl();
    EXPECT_NE(glsl.find("#define SETTINGS_COMPOSITING_ALPHA 0\n"), std::string::npos);
    EXPECT_NE(glsl.find("#define SETTINGS_COMPOSITING_EXTINCTION 1\n"), std::string::npos);
    EXPECT_NE(glsl.find("#define SETTINGS_LIGHT_BUFFER_BUILDER_MULTI_SLICE 1\n"),
              std::string::npos);
    EXPECT_NE(glsl.find("#define SETTINGS_MODE_REFERENCE 6\n"), std::string::npos);
    EXPECT_NE(glsl.find("    int compositing;"), std::string::npos);
    EXPECT_NE(glsl.find("    vec3 background;"), std::string::npos);
    EXPECT_NE(glsl.find("    ivec2 size;"), std::string::npos);
}

TEST_F(SettingsBlockTest, EveryRequestSettingReadsBackInTheShaderByItsName) {
    auto context = gpu::Context::create();
    ASSERT_TRUE(context.ok()) << context.error().to_string();
    const std::vector<const scene::Setting*> rows = frame_rows();
    ASSERT_FALSE(rows.empty());
    const scene::FrameRequest request = distinctive_request(rows);

    std::vector<float> expected;
    std::vector<float> numbers;
    std::vector<std::string> names;
    std::string body;
    for (const scene::Setting* row : rows) {
        const scene::SettingValue value = row->read_frame(request);
        for (std::size_t i = 0; i < components_of(*row); ++i) {
            const std::string component =
                    components_of(*row) == 1 ? "" : std::string("[") + std::to_string(i) + "]";
            body += "    values[" + std::to_string(expected.size()) + "] = float(settings." +
                    settings_member_name(row->path) + component + ");\n";
            expected.push_back(static_cast<float>(value[static_cast<int>(i)]));
            names.push_back(std::string(row->path) + component);
            if (row->kind == scene::SettingKind::number ||
                row->kind == scene::SettingKind::vector) {
                numbers.push_back(expected.back());
            }
        }
    }
    ASSERT_EQ(std::set<float>(numbers.begin(), numbers.end()).size(), numbers.size())
            << "the test's values are not distinct";
    std::ofstream(root_ / "read_settings.comp")
            << "#include \"" << settings_block_file << "\"\n"
            << "layout(local_size_x = 1) in;\n"
            << "layout(std430, binding = 0) writeonly buffer Values { float values[]; };\n"
            << "void main() {\n"
            << body << "}\n";
    gpu::ShaderLibrary library(root_, {{std::string(settings_block_file), settings_block_glsl()}});
    auto program = library.build_compute("read_settings.comp", {});
    ASSERT_TRUE(program.ok()) << program.error().to_string();

    // The driver's std140 layout of the block agrees with the offsets the C++ side writes at.
    const GLuint block = glGetProgramResourceIndex(program->name(), GL_UNIFORM_BLOCK, "Settings");
    ASSERT_NE(block, GL_INVALID_INDEX);
    const GLenum size_property = GL_BUFFER_DATA_SIZE;
    GLint block_size = 0;
    glGetProgramResourceiv(program->name(), GL_UNIFORM_BLOCK, block, 1, &size_property, 1, nullptr,
                           &block_size);
    EXPECT_LE(static_cast<std::size_t>(block_size), settings_block_bytes());
    ASSERT_EQ(settings_members().size(), rows.size());
    for (const SettingsMember& member : settings_members()) {
        const std::string name = "Settings." + member.name;
        const GLuint index = glGetProgramResourceIndex(program->name(), GL_UNIFORM, name.c_str());
        ASSERT_NE(index, GL_INVALID_INDEX) << name;
        const GLenum offset_property = GL_OFFSET;
        GLint offset = -1;
        glGetProgramResourceiv(program->name(), GL_UNIFORM, index, 1, &offset_property, 1, nullptr,
                               &offset);
        EXPECT_EQ(static_cast<std::size_t>(offset), member.offset) << name;
    }

    const std::vector<std::byte> data = settings_block_data(request);
    ASSERT_EQ(data.size(), settings_block_bytes());
    gpu::Buffer settings = gpu::create_buffer();
    glNamedBufferStorage(settings.name(), static_cast<GLsizeiptr>(data.size()), data.data(), 0);
    glBindBufferBase(GL_UNIFORM_BUFFER, settings_block_binding, settings.name());
    gpu::Buffer values = gpu::create_buffer();
    const auto values_bytes = static_cast<GLsizeiptr>(sizeof(float) * expected.size());
    glNamedBufferStorage(values.name(), values_bytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, values.name());
    glUseProgram(program->name());
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> read_back(expected.size(), -1.0f);
    glGetNamedBufferSubData(values.name(), 0, values_bytes, read_back.data());
    ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    for (std::size_t i = 0; i < expected.size(); ++i) {
        EXPECT_EQ(read_back[i], expected[i]) << names[i];
    }
}

}  // namespace
}  // namespace penumbra::render
