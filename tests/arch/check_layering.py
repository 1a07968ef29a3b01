#!/usr/bin/env python3
"""Checks the module rules of STYLE.md §8 on server/: every `#include <penumbra/M/...>` and every
name qualified by a module, `M::` or `penumbra::M` (a `using` declaration, a namespace alias or a
`namespace penumbra::M` block included; comments and string literals are not code), is an edge to
a module the module declares itself (its DEPENDS and PRIVATE_DEPENDS; what those pass on does not
count: a module names each module it uses), declared dependencies are those STYLE.md's table
allows, app's included, and each confined third-party library is included only by the modules that
own it. Prints every violation as file:line and exits 1 if there is any.

  check_layering.py --root server            check the tree
  check_layering.py --self-test              check that a planted violation of each kind is found
"""
import argparse
import pathlib
import re
import sys
import tempfile

# STYLE.md §8's table: the modules each module may declare as dependencies (all lower in the
# layering picture, or beside it where the table says so: optics uses scene).
ALLOWED_DEPENDENCIES = {
    "base": set(),
    "volume": {"base"},
    "scene": {"base"},
    "optics": {"scene", "base"},
    "reference": {"volume", "scene", "optics", "base"},
    "gpu": {"base"},
    "render": {"volume", "scene", "optics", "base", "gpu"},
    "encode": {"base"},
    # protocol names the formats frames are written in from encode's table.
    "protocol": {"encode", "scene", "base"},
    "metrics": {"base"},
    "quality": {"render", "encode", "volume", "scene", "base"},
    # The benchmarks and their reports, over quality's table and sweep; only app links them.
    "bench": {"quality", "render", "encode", "volume", "scene", "base"},
    "session": {"quality", "render", "encode", "volume", "scene", "metrics", "base"},
    # net translates session's state, volumes and frames (in session's terms) into protocol
    # messages; scene's types are the vocabulary of both.
    "net": {"session", "protocol", "metrics", "scene", "base"},
    # The command line's vocabulary: frame options read into scene's requests, transfer-function
    # files in the protocol's shape.
    "cli": {"protocol", "volume", "scene", "base"},
}
# app, the executable, is over every module; it declares what it links like any other.
ALLOWED_DEPENDENCIES["app"] = set(ALLOWED_DEPENDENCIES) - {"gpu"}
MODULES = set(ALLOWED_DEPENDENCIES)

# Third-party headers (by the longest leading part of the include path listed) and the modules they
# are confined to. quality reads and writes the accuracy tables' JSON files; app may use nlohmann for
# a file of its own; cli holds Boost.Program_options, and app describes its commands' options in
# cli's terms (STYLE.md §8.1).
CONFINED = {
    "nlohmann": {"protocol", "quality", "app"},
    "OpenImageIO": {"encode"},
    "boost": {"net"}, "boost/program_options": {"cli"},
    "epoxy": {"gpu"}, "EGL": {"gpu"}, "GL": {"gpu"},
    "nifti1_io.h": {"volume"}, "nifti2_io.h": {"volume"}, "zlib.h": {"volume"},
    "dcmtk": {"volume"},
    "openssl": {"session"},
}

INCLUDE = re.compile(r'^\s*#\s*include\s*<([^>]+)>')
# A module named in code: `M::name`, `penumbra::M` (a namespace block, a using directive or an
# alias), `namespace M {` nested in penumbra, `using namespace M;` and `namespace x = M;`.
# What stands after `::` (a member, a nested name) is not a module, hence the look-behind.
QUALIFIED_NAMES = [
    re.compile(r'(?<![\w:])(?:::)?(?:penumbra::)?([A-Za-z_]\w*)::(~?\w*)'),
    re.compile(r'(?<![\w:])(?:::)?penumbra::([A-Za-z_]\w*)\b(?!::)'),
    re.compile(r'\bnamespace\s+([A-Za-z_]\w*)\s*\{'),
    re.compile(r'\busing\s+namespace\s+(?:::)?([A-Za-z_]\w*)\s*;'),
    re.compile(r'\bnamespace\s+\w+\s*=\s*(?:::)?([A-Za-z_]\w*)\s*;'),
]
# R"delimiter( ... )delimiter", with an encoding prefix or none.
RAW_STRING = re.compile(r'(?:u8|u|U|L)?R"([^()\\\s]{0,16})\(')
MODULE_CALL = re.compile(r'penumbra_add_module\s*\(([^)]*)\)', re.S)
KEYWORDS = {"SOURCES", "DEPENDS", "PRIVATE_DEPENDS", "LIBS", "PRIVATE_LIBS"}
# app is a plain library and executable: its modules are the penumbra::M it links.
LINKED_MODULE = re.compile(r'\bpenumbra::(\w+)')


def declared_dependencies(root):
    """{module: (public deps, private deps)} from each module's penumbra_add_module call, and for
    app the penumbra:: targets its CMakeLists links."""
    modules = {}
    for cmake in sorted(root.glob("*/CMakeLists.txt")):
        text = cmake.read_text()
        match = MODULE_CALL.search(text)
        if not match:
            if cmake.parent.name == "app":
                modules["app"] = (set(LINKED_MODULE.findall(text)), set())
            continue
        words = match.group(1).split()
        name, lists, current = words[0], {k: [] for k in KEYWORDS}, None
        for word in words[1:]:
            if word in KEYWORDS:
                current = word
            elif current:
                lists[current].append(word)
        modules[name] = (set(lists["DEPENDS"]), set(lists["PRIVATE_DEPENDS"]))
    return modules


def includable(module, modules):
    """What a module may include: its own headers and those of the modules it declares, directly.
    A module that another one passes on publicly is not among them: its edge must be declared."""
    public, private = modules.get(module, (set(), set()))
    return {module} | public | private


def code_of(text):
    """`text` with its comments and string and character literals (raw strings included) blanked
    out, newlines kept, so that what is left is code and its line numbers are the file's."""
    out = []
    i, n = 0, len(text)

    def blank(part):
        out.append(re.sub(r'[^\n]', ' ', part))

    while i < n:
        c = text[i]
        if text.startswith('//', i):
            end = text.find('\n', i)
            end = n if end < 0 else end
            blank(text[i:end])
            i = end
        elif text.startswith('/*', i):
            end = text.find('*/', i + 2)
            end = n if end < 0 else end + 2
            blank(text[i:end])
            i = end
        elif c in 'uULR' and (raw := RAW_STRING.match(text, i)) and \
                (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == '_')):
            close = ')' + raw.group(1) + '"'
            end = text.find(close, raw.end())
            end = n if end < 0 else end + len(close)
            blank(text[i:end])
            i = end
        elif c == '"' or (c == "'" and not (i > 0 and text[i - 1].isalnum())):
            # A quote after a digit or letter is a digit separator (10'000), not a literal.
            j = i + 1
            while j < n and text[j] != c and text[j] != '\n':
                j += 2 if text[j] == '\\' else 1
            end = min(j + 1, n)
            blank(text[i:end])
            i = end
        else:
            out.append(c)
            i += 1
    return ''.join(out)


def named_modules(line):
    """The modules a line of code names, each with the text that names it."""
    found = {}
    for pattern in QUALIFIED_NAMES:
        for match in pattern.finditer(line):
            target = match.group(1)
            if target in MODULES and target not in found:
                found[target] = " ".join(match.group(0).split()).rstrip(" {;")
    return found


def check(root):
    problems = []
    modules = declared_dependencies(root)
    for module, (public, private) in modules.items():
        for dependency in sorted((public | private) - ALLOWED_DEPENDENCIES.get(module, set())):
            problems.append(f"{root / module / 'CMakeLists.txt'}: {module} must not depend on "
                            f"{dependency} (STYLE.md §8)")
    for folder in sorted(p for p in root.iterdir() if p.is_dir() and p.name in MODULES):
        module = folder.name
        allowed = includable(module, modules)
        for path in sorted(folder.rglob("*")):
            if path.suffix not in {".hpp", ".cpp", ".h"}:
                continue
            text = path.read_text(errors="replace")
            for number, line in enumerate(code_of(text).splitlines(), 1):
                for target, named in named_modules(line).items():
                    if target not in allowed:
                        problems.append(f"{path}:{number}: {module} names {named}, but does not "
                                        f"declare {target}")
            for number, line in enumerate(text.splitlines(), 1):
                match = INCLUDE.match(line)
                if not match:
                    continue
                header = match.group(1)
                first = header.split("/")[0]
                if first == "penumbra" and "/" in header:
                    target = header.split("/")[1]
                    if target not in allowed:
                        problems.append(f"{path}:{number}: {module} includes {header}, but "
                                        f"does not declare {target}")
                elif (confined := confined_as(header)) and module not in CONFINED[confined]:
                    owners = ", ".join(sorted(CONFINED[confined]))
                    problems.append(f"{path}:{number}: {module} includes {header}, which is "
                                    f"confined to {owners}")
    return problems


def confined_as(header):
    """The key of CONFINED that names `header` most closely ("boost/program_options" before
    "boost"), or None."""
    names = [key for key in CONFINED
             if header == key or header.startswith(key + "/") or header.startswith(key + ".")]
    return max(names, key=len, default=None)


def self_test():
    """Plants one violation of each kind in a small tree; each must be reported."""
    with tempfile.TemporaryDirectory() as directory:
        root = pathlib.Path(directory)

        def module(name, cmake, files):
            (root / name / "src").mkdir(parents=True)
            (root / name / "CMakeLists.txt").write_text(cmake)
            for file_name, text in files.items():
                (root / name / "src" / file_name).write_text(text)

        module("base", "penumbra_add_module(base SOURCES src/a.cpp)",
               {"a.cpp": "const ::penumbra::render::Frame* frame = nullptr;\n"})
        module("gpu", "penumbra_add_module(gpu SOURCES src/a.cpp DEPENDS base)",
               {"a.cpp": "#include <epoxy/gl.h>\n"})
        module("render", "penumbra_add_module(render SOURCES src/a.cpp DEPENDS base "
               "PRIVATE_DEPENDS gpu)", {"a.cpp": "#include <penumbra/gpu/context.hpp>\n"})
        module("session", "penumbra_add_module(session SOURCES src/a.cpp DEPENDS render)",
               {"a.cpp": "#include <penumbra/render/renderer.hpp>\n"
                         "#include <penumbra/gpu/context.hpp>\n"
                         "#include <OpenImageIO/imageio.h>\n"
                         "namespace penumbra::session {\n"
                         "// gpu::Context, in a comment\n"
                         "/* gpu::Context, in a block\n   comment */\n"
                         "const char* text = \"gpu::Context, in a string\";\n"
                         "const char* raw = R\"x(gpu::Context, \"in\" a raw string)x\";\n"
                         "const int many = 10'000;  // a digit separator, not a literal\n"
                         "const char quote = '\"';\n"
                         "session::Session* own = nullptr;\n"
                         "std::unique_ptr<render::Renderer> declared;\n"
                         "gpu::Context* context = nullptr;\n"
                         "}  // namespace penumbra::session\n"})
        module("volume", "penumbra_add_module(volume SOURCES src/a.cpp DEPENDS base session)",
               {"a.cpp": "#include <zlib.h>\n"})
        module("net", "penumbra_add_module(net SOURCES src/a.cpp DEPENDS session)",
               {"a.cpp": "#include <penumbra/session/session.hpp>\n"
                         "#include <penumbra/render/renderer.hpp>\n"
                         "using namespace penumbra::volume;\n"})
        module("cli", "penumbra_add_module(cli SOURCES src/a.cpp DEPENDS base)",
               {"a.cpp": "#include <boost/program_options.hpp>\n"
                         "namespace penumbra::encode {}\n"})
        module("app", "target_link_libraries(penumbra_app_lib PUBLIC penumbra::net penumbra::gpu)",
               {"a.cpp": "#include <penumbra/net/server.hpp>\n"
                         "#include <penumbra/session/session.hpp>\n"
                         "#include <boost/program_options.hpp>\n"
                         "#include <boost/beast/core.hpp>\n"})
        found = "\n".join(check(root))
        expected = [
            "session includes penumbra/gpu/context.hpp",  # render links gpu PRIVATE
            "session includes OpenImageIO/imageio.h",      # confined to encode
            "volume must not depend on session",  # upward
            "net includes penumbra/render/renderer.hpp",  # session passes render on, undeclared
            "app includes penumbra/session/session.hpp",  # app declares only net
            "app must not depend on gpu",  # gpu stays inside render
            "app includes boost/beast/core.hpp",  # Boost.Beast is net's
            "app includes boost/program_options.hpp",  # cli's
            # Names in code: a qualified name, a using directive, a namespace block (each module
            # declares what it names, and the comments and strings above name nothing).
            "base names ::penumbra::render::Frame",
            "session names gpu::Context",
            "net names penumbra::volume",
            "cli names penumbra::encode",
        ]
        missing = [text for text in expected if text not in found]
        unexpected = [line for line in found.splitlines()
                      if not any(text in line for text in expected)]
        if missing or unexpected:
            print("self-test failed\nmissing: %s\nunexpected: %s" % (missing, unexpected))
            return 1
        print("self-test: every planted violation found, nothing else")
        return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", type=pathlib.Path, help="the server/ folder")
    parser.add_argument("--self-test", action="store_true")
    args = parser.parse_args()
    if args.self_test:
        return self_test()
    if not args.root:
        parser.error("--root or --self-test")
    problems = check(args.root)
    for problem in problems:
        print(problem)
    if problems:
        print(f"{len(problems)} layering violation(s)")
        return 1
    print(f"layering: {len(declared_dependencies(args.root))} modules (app among them) checked, "
          "no violations")
    return 0


if __name__ == "__main__":
    sys.exit(main())
