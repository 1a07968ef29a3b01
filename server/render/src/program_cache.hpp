#pragma once

#include <penumbra/base/result.hpp>
#include <penumbra/gpu/objects.hpp>
#include <penumbra/gpu/shader_library.hpp>

#include <functional>
#include <map>
#include <string>

namespace penumbra::render {

// Every compiled program of the renderer, for its life, shared by all passes: a program is known
// by its stage files and defines, so no pass compiles what another one already has (the ray
// caster and half-angle slicing share resolve.comp).
class ProgramCache {
public:
    explicit ProgramCache(const gpu::ShaderLibrary& shaders)
        : shaders_(shaders) {}

    ProgramCache(const ProgramCache&) = delete;
    ProgramCache& operator=(const ProgramCache&) = delete;

    base::Result<const gpu::Program*> compute(const std::string& file,
                                              const gpu::Defines& defines = {});

    base::Result<const gpu::Program*> graphics(const std::string& vertex_file,
                                               const std::string& fragment_file,
                                               const gpu::Defines& defines = {});

    // Programs compiled so far.
    [[nodiscard]] std::size_t size() const { return programs_.size(); }

private:
    base::Result<const gpu::Program*> find_or_build(
            std::string key, const gpu::Defines& defines,
            const std::function<base::Result<gpu::Program>()>& build);

    const gpu::ShaderLibrary& shaders_;
    std::map<std::string, gpu::Program> programs_;
};

}  // namespace penumbra::render
