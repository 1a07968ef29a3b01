// The generated Settings block seen from a shader: every request setting of scene::kSettingRanges,
// set to a value of its own, reads back in GLSL under its name with that value, at the offset the
// C++ side writes it to. A row the declaration or the buffer missed, a swapped pair or a std140
// offset the driver lays out differently fails here.

#include "settings_block.hpp"

#include <penumbra/gpu/context.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/gpu/shader_library.hpp>

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

// The rows a request holds, straight from the table (not through settings_members()).
std::vector<const scene::SettingRange*> request_rows() {
    std::vector<const scene::SettingRange*> rows;
    for (const scene::SettingRange* row : scene::kSettingRanges) {
        if (row->read != nullptr) {
            rows.push_back(row);
        }
    }
    return rows;
}

// Each row at its own fraction of its range, so that no two members share a value and a
// member read from another's place shows.
scene::FrameRequest distinctive_request(const std::vector<const scene::SettingRange*>& rows) {
    scene::FrameRequest request;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const scene::SettingRange& row = *rows[i];
        const double fraction = static_cast<double>(i + 1) / static_cast<double>(rows.size() + 1);
        double value = row.min + (row.max - row.min) * fraction;
        if (row.integer) {
            value = std::round(value);
        }
        row.write(request, value);
    }
    return request;
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

TEST_F(SettingsBlockTest, EveryRequestSettingReadsBackInTheShaderByItsName) {
    auto context = gpu::Context::create();
    ASSERT_TRUE(context.ok()) << context.error().to_string();
    const std::vector<const scene::SettingRange*> rows = request_rows();
    ASSERT_FALSE(rows.empty());
    const scene::FrameRequest request = distinctive_request(rows);

    std::vector<float> expected;
    std::string body;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        expected.push_back(static_cast<float>(rows[i]->read(request)));
        body += "    values[" + std::to_string(i) + "] = float(settings." +
                settings_member_name(rows[i]->field) + ");\n";
    }
    ASSERT_EQ(std::set<float>(expected.begin(), expected.end()).size(), expected.size())
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
    const auto values_bytes = static_cast<GLsizeiptr>(sizeof(float) * rows.size());
    glNamedBufferStorage(values.name(), values_bytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, values.name());
    glUseProgram(program->name());
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> read_back(rows.size(), -1.0f);
    glGetNamedBufferSubData(values.name(), 0, values_bytes, read_back.data());
    ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    for (std::size_t i = 0; i < rows.size(); ++i) {
        EXPECT_EQ(read_back[i], expected[i]) << rows[i]->field;
    }
}

}  // namespace
}  // namespace penumbra::render
