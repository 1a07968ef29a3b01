#include <penumbra/gpu/context.hpp>
#include <penumbra/gpu/shader_library.hpp>

#include <gtest/gtest.h>

#include <fstream>

namespace penumbra::gpu {
namespace {

class ShaderLibraryTest : public ::testing::Test {
protected:
    void SetUp() override {
        root_ = std::filesystem::temp_directory_path() /
                ("penumbra_shaders_" + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(root_ / "include");
    }

    void TearDown() override { std::filesystem::remove_all(root_); }

    void write(const std::string& file, const std::string& text) {
        std::ofstream(root_ / file) << text;
    }

    std::filesystem::path root_;
};

TEST_F(ShaderLibraryTest, ExpandsIncludesOnceWithLineDirectivesAndDefines) {
    write("include/common.glsl", "float twice(float x) { return 2.0 * x; }\n");
    write("include/user.glsl",
          "#include \"include/common.glsl\"\nfloat four(float x) { return twice(twice(x)); }\n");
    write("main.comp",
          "#include \"include/common.glsl\"\n#include \"include/user.glsl\"\nvoid main() {}\n");
    ShaderLibrary library(root_);
    auto source = library.expand("main.comp", {{"FLAG", "1"}});
    ASSERT_TRUE(source.ok()) << source.error().to_string();
    EXPECT_EQ(source->text.rfind("#version 450 core\n#define FLAG 1\n", 0), 0u);
    EXPECT_EQ(source->files,
              (std::vector<std::string>{"main.comp", "include/common.glsl", "include/user.glsl"}));
    // common.glsl is pasted once although two files include it.
    const std::string& text = source->text;
    EXPECT_EQ(text.find("float twice"), text.rfind("float twice"));
    EXPECT_NE(text.find("#line 3 0\nvoid main"), std::string::npos);
}

TEST_F(ShaderLibraryTest, MissingIncludeNamesTheIncludingFileAndLine) {
    write("main.comp", "// header\n#include \"include/absent.glsl\"\nvoid main() {}\n");
    ShaderLibrary library(root_);
    auto source = library.expand("main.comp", {});
    ASSERT_FALSE(source.ok());
    EXPECT_EQ(source.error().where, "main.comp:2");
}

TEST_F(ShaderLibraryTest, IncludeCycleEndsBecauseEachFileIsPastedOnce) {
    write("include/a.glsl", "#include \"include/b.glsl\"\nfloat a;\n");
    write("include/b.glsl", "#include \"include/a.glsl\"\nfloat b;\n");
    write("main.comp", "#include \"include/a.glsl\"\n");
    ShaderLibrary library(root_);
    auto source = library.expand("main.comp", {});
    ASSERT_TRUE(source.ok());
    EXPECT_EQ(source->files.size(), 3u);
    EXPECT_LT(source->text.find("float b;"), source->text.find("float a;"));
}

TEST_F(ShaderLibraryTest, GeneratedFileIsIncludedByItsPathBeforeTheFolder) {
    write("include/made.glsl", "float from_the_folder;\n");
    write("main.comp",
          "#include \"include/made.glsl\"\n#include \"include/made.glsl\"\nvoid main() {}\n");
    ShaderLibrary library(root_, {{"include/made.glsl", "float made_here;\nfloat second_line;\n"}});
    auto source = library.expand("main.comp", {});
    ASSERT_TRUE(source.ok()) << source.error().to_string();
    EXPECT_EQ(source->files, (std::vector<std::string>{"main.comp", "include/made.glsl"}));
    const std::string& text = source->text;
    EXPECT_EQ(text.find("from_the_folder"), std::string::npos);
    EXPECT_NE(text.find("#line 1 1\nfloat made_here;\nfloat second_line;\n#line 2 0\n"),
              std::string::npos)
            << text;
    EXPECT_EQ(text.find("made_here"), text.rfind("made_here"));
}

TEST_F(ShaderLibraryTest, CompileErrorPointsAtTheIncludedFileAndLine) {
    auto context = Context::create();
    ASSERT_TRUE(context.ok()) << context.error().to_string();
    write("include/broken.glsl",
          "float ok() { return 1.0; }\n\nfloat bad() { return undefined_name; }\n");
    write("main.comp",
          "layout(local_size_x = 1) in;\n#include \"include/broken.glsl\"\nvoid main() {}\n");
    ShaderLibrary library(root_);
    auto program = library.build_compute("main.comp", {});
    ASSERT_FALSE(program.ok());
    EXPECT_NE(program.error().message.find("include/broken.glsl:3"), std::string::npos)
            << program.error().message;
}

TEST_F(ShaderLibraryTest, BuildsAWorkingComputeProgramWithDefines) {
    auto context = Context::create();
    ASSERT_TRUE(context.ok());
    write("main.comp",
          "layout(local_size_x = 1) in;\nlayout(std430, binding = 0) buffer Out { float v; };\n"
          "void main() { v = VALUE; }\n");
    ShaderLibrary library(root_);
    auto program = library.build_compute("main.comp", {{"VALUE", "42.5"}});
    ASSERT_TRUE(program.ok()) << program.error().to_string();
    Buffer buffer = create_buffer();
    glNamedBufferStorage(buffer.name(), sizeof(float), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffer.name());
    glUseProgram(program->name());
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    float value = 0.0f;
    glGetNamedBufferSubData(buffer.name(), 0, sizeof(float), &value);
    EXPECT_EQ(value, 42.5f);
}

TEST(ResolveLogLines, MapsMesaAndNvidiaFormats) {
    const std::vector<std::string> files = {"raycast.comp", "include/ray.glsl"};
    EXPECT_EQ(resolve_log_lines("1:12(3): error: `x' undeclared\n", files),
              "include/ray.glsl:12:3: error: `x' undeclared\n");
    EXPECT_EQ(resolve_log_lines("0(7) : error C1008: undefined variable\n", files),
              "raycast.comp:7: error C1008: undefined variable\n");
    EXPECT_EQ(resolve_log_lines("something else\n", files), "something else\n");
}

}  // namespace
}  // namespace penumbra::gpu
