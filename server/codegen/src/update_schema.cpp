// Writes the generated parts of proto/v1/common.schema.json and hello.schema.json, proto/README.md
// and the hello the web client's tests recorded (schema_generator.hpp) into them, and the web
// client's module of the server's names and views whole: update_schema PROTO_DIR.
// scripts/update-schema.sh builds and runs it.

#include <penumbra/base/result.hpp>
#include <penumbra/codegen/schema_generator.hpp>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <iterator>
#include <string>
#include <string_view>

namespace {

// Rewrites `path` with what `generate` makes of its text (empty for a file not written yet);
// false (and a message) on an error.
bool update(const std::filesystem::path& path,
            const std::function<penumbra::base::Result<std::string>(std::string_view)>& generate) {
    std::string committed;
    if (std::filesystem::exists(path)) {
        std::ifstream in(path, std::ios::binary);
        if (!in) {
            std::cerr << "update_schema: cannot read " << path.string() << "\n";
            return false;
        }
        committed.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const auto generated = generate(committed);
    if (!generated) {
        std::cerr << "update_schema: " << path.string() << ": " << generated.error().to_string()
                  << "\n";
        return false;
    }
    if (*generated == committed) {
        std::cout << path.string() << " is up to date\n";
        return true;
    }
    std::filesystem::create_directories(path.parent_path());
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << *generated;
    if (!out.flush()) {
        std::cerr << "update_schema: cannot write " << path.string() << "\n";
        return false;
    }
    std::cout << path.string() << " rewritten\n";
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: update_schema PROTO_DIR   (the repository's proto/)\n";
        return 2;
    }
    namespace protocol_test = penumbra::codegen;
    const std::filesystem::path proto = argv[1];
    const bool schema = update(proto / "v1" / "common.schema.json", [](std::string_view text) {
        return protocol_test::generated_common_schema(text);
    });
    const bool hello = update(proto / "v1" / "hello.schema.json", [](std::string_view text) {
        return protocol_test::generated_hello_schema(text);
    });
    const bool readme = update(proto / "README.md", [&](std::string_view text) {
        return protocol_test::generated_readme(text, proto / "v1");
    });
    const bool recorded_hello = update(
            proto.parent_path() / "client_web" / "test" / "fixtures" / "server_messages.jsonl",
            [](std::string_view text) { return protocol_test::generated_recorded_hello(text); });
    const bool client_tables =
            update(proto.parent_path() / "client_web" / protocol_test::kClientTablesPath,
                   [](std::string_view) { return protocol_test::generated_client_tables(); });
    return schema && hello && readme && recorded_hello && client_tables ? 0 : 1;
}
