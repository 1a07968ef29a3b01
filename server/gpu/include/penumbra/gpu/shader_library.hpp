#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/gpu/objects.hpp>

#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::gpu {

// A variant is a set of preprocessor definitions injected after `#version 450 core`.
using Defines = std::vector<std::pair<std::string, std::string>>;

// Shader files made by the program rather than read from the folder, by the path an `#include`
// names them with (a declaration that C++ derives from its own tables, so the two cannot drift).
using GeneratedFiles = std::map<std::string, std::string, std::less<>>;

// GLSL source after #include expansion, and the file each GLSL source-string number stands for.
// `#line <line> <file index>` precedes every chunk so compile errors point at the right file.
struct ExpandedSource {
    std::string text;
    std::vector<std::string> files;  // index = the source-string number in #line
};

// Loads shaders from a folder (`shaders/` of the source tree), expands `#include "path"` relative
// to that folder (each file once per program, like #pragma once), injects the version and the
// defines, compiles and links. Compile and link errors come back as Errors whose message names
// the file and line of the offending source, not the position in the expanded text. A path in
// `generated` is included from there instead of the folder.
class ShaderLibrary {
public:
    explicit ShaderLibrary(std::filesystem::path root, GeneratedFiles generated = {});

    [[nodiscard]] const std::filesystem::path& root() const { return root_; }

    base::Result<ExpandedSource> expand(const std::string& file, const Defines& defines) const;

    base::Result<Program> build_compute(const std::string& file, const Defines& defines) const;

    base::Result<Program> build_graphics(const std::string& vertex_file,
                                         const std::string& fragment_file,
                                         const Defines& defines) const;

private:
    base::Result<Shader> compile(GLenum stage, const std::string& file,
                                 const Defines& defines) const;

    std::filesystem::path root_;
    GeneratedFiles generated_;
};

// Rewrites driver messages such as "0:12(3): error: ..." (Mesa) or "0(12) : error ..." (NVIDIA)
// into "file.glsl:12: error: ..." using the file table of an ExpandedSource.
std::string resolve_log_lines(const std::string& log, const std::vector<std::string>& files);

// Finds the shader folder: $PENUMBRA_SHADER_DIR, else share/penumbra/shaders above the executable
// (base::data_dir: an install prefix, or a build tree's links into the source tree).
std::filesystem::path default_shader_dir();

}  // namespace penumbra::gpu
