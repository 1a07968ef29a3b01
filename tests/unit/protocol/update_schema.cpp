// Writes the generated parts of proto/v1/common.schema.json (schema_generator.hpp) into the file
// given: update_schema proto/v1/common.schema.json. scripts/update-schema.sh builds and runs it.

#include "schema_generator.hpp"

#include <fstream>
#include <iostream>
#include <iterator>
#include <string>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: update_schema PATH/TO/common.schema.json\n";
        return 2;
    }
    const std::string path = argv[1];
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        std::cerr << "update_schema: cannot read " << path << "\n";
        return 1;
    }
    const std::string committed{std::istreambuf_iterator<char>(in),
                                std::istreambuf_iterator<char>()};
    in.close();
    const auto generated = penumbra::protocol::test::generated_common_schema(committed);
    if (!generated) {
        std::cerr << "update_schema: " << path << ": " << generated.error().to_string() << "\n";
        return 1;
    }
    if (*generated == committed) {
        std::cout << path << " is up to date\n";
        return 0;
    }
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << *generated;
    if (!out.flush()) {
        std::cerr << "update_schema: cannot write " << path << "\n";
        return 1;
    }
    std::cout << path << " rewritten from the C++ tables\n";
    return 0;
}
