#!/usr/bin/env python3
"""Checks the module rules on server/ against the module table of docs/CONTRIBUTING.md ("Modules":
module, layer, responsibility, allowed dependencies, confined third-party headers): every
`#include <penumbra/M/...>` and every name qualified by a module, `M::` or `penumbra::M` (a `using`
declaration, a namespace alias or a `namespace penumbra::M` block included; comments and string
literals are not code), is an edge to a module the module declares itself (its DEPENDS and
PRIVATE_DEPENDS; what those pass on does not count: a module names each module it uses), declared
dependencies are those the table allows, app's included, and each confined third-party library is
included only by the modules that own it. Prints every violation as file:line and exits 1 if there
is any; exits 2, saying why, where the table is missing or malformed.

  check_layering.py --root server            check the tree
  check_layering.py --self-test              check that a planted violation of each kind is found,
                                             and that a broken table is refused
"""
import argparse
import dataclasses
import pathlib
import re
import sys
import tempfile

# The module table, and the words of its section and columns.
TABLE = pathlib.Path(__file__).resolve().parents[2] / "docs" / "CONTRIBUTING.md"
SECTION = "## Modules"
COLUMNS = ["module", "layer", "responsibility", "allowed dependencies",
           "confined third-party headers"]
NOTHING = {"–", "-", ""}  # a cell that lists nothing


class TableError(Exception):
    """The module table is missing, or a row of it cannot be read."""


@dataclasses.dataclass
class Rules:
    """What the table says: the modules each module may declare, and for each third-party header
    (by the longest leading part of its include path listed) the modules it is confined to."""
    allowed: dict
    confined: dict

    @property
    def modules(self):
        return set(self.allowed)


def cells(line):
    return [cell.strip() for cell in line.strip().strip("|").split("|")]


def names_in(cell, where, column):
    """The `names` of a cell, comma-separated, each in backticks; none for a dash."""
    if cell in NOTHING:
        return []
    names = []
    for item in (part.strip() for part in cell.split(",")):
        match = re.fullmatch(r"`([^`\s]+)`", item)
        if not match:
            raise TableError(f"{where}: '{item}' in the {column} column is not a `name` in "
                             "backticks (a dash for none)")
        names.append(match.group(1))
    return names


def parse_rules(text, where):
    """The rules of the table in the Modules section of `text` (the file `where`)."""
    lines = text.splitlines()
    start = next((i for i, line in enumerate(lines) if line.strip() == SECTION), None)
    if start is None:
        raise TableError(f"{where}: no '{SECTION}' section, where the module table belongs")
    first = next((i for i in range(start + 1, len(lines))
                  if lines[i].startswith("|") or lines[i].startswith("## ")), None)
    if first is None or not lines[first].startswith("|"):
        raise TableError(f"{where}:{start + 1}: the '{SECTION}' section has no table")
    if [cell.lower() for cell in cells(lines[first])] != COLUMNS:
        raise TableError(f"{where}:{first + 1}: the module table's columns must be "
                         f"{' | '.join(COLUMNS)}")
    rule = cells(lines[first + 1]) if first + 1 < len(lines) else []
    if len(rule) != len(COLUMNS) or not all(re.fullmatch(r":?-+:?", cell) for cell in rule):
        raise TableError(f"{where}:{first + 2}: the module table's header row is not followed "
                         "by its |---| row")
    layers, allowed, confined = {}, {}, {}
    number = first + 2
    while number < len(lines) and lines[number].startswith("|"):
        row, at = cells(lines[number]), f"{where}:{number + 1}"
        number += 1
        if len(row) != len(COLUMNS):
            raise TableError(f"{at}: {len(row)} cells where the table has {len(COLUMNS)}")
        names = names_in(row[0], at, "module")
        if len(names) != 1:
            raise TableError(f"{at}: a row names one `module`")
        module = names[0]
        if module in layers:
            raise TableError(f"{at}: {module} has a row already")
        if not row[1].isdigit():
            raise TableError(f"{at}: {module}'s layer '{row[1]}' is not a whole number")
        if not row[2]:
            raise TableError(f"{at}: {module} has no responsibility")
        layers[module] = int(row[1])
        allowed[module] = set(names_in(row[3], at, "allowed dependencies"))
        for header in names_in(row[4], at, "confined third-party headers"):
            confined.setdefault(header, set()).add(module)
    if not layers:
        raise TableError(f"{where}:{first + 1}: the module table has no rows")
    for module, dependencies in allowed.items():
        for dependency in sorted(dependencies):
            if dependency not in layers:
                raise TableError(f"{where}: {module} may depend on {dependency}, which has no row")
            if dependency == module or layers[dependency] > layers[module]:
                raise TableError(f"{where}: {module} (layer {layers[module]}) may not depend on "
                                 f"{dependency} (layer {layers[dependency]}): dependencies "
                                 "point down or beside")
    if cycle := dependency_cycle(allowed):
        raise TableError(f"{where}: the allowed dependencies go round: {' -> '.join(cycle)}")
    return Rules(allowed, confined)


def dependency_cycle(allowed):
    """Modules that depend on each other in a ring (beside one another on a layer), or None."""
    done = set()

    def visit(module, path):
        if module in path:
            return path[path.index(module):] + [module]
        if module in done:
            return None
        for dependency in sorted(allowed[module]):
            if cycle := visit(dependency, path + [module]):
                return cycle
        done.add(module)
        return None

    return next((cycle for module in sorted(allowed) if (cycle := visit(module, []))), None)


def read_rules(path):
    try:
        text = path.read_text()
    except OSError as error:
        raise TableError(f"{path}: the module table cannot be read ({error.strerror})")
    return parse_rules(text, path)


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
# app and codegen are plain libraries and executables: their modules are the penumbra::M they link.
LINKED_MODULE = re.compile(r'\bpenumbra::(\w+)')


def declared_dependencies(root):
    """{module: (public deps, private deps)} from each module's penumbra_add_module call, and for
    a folder without one (app, codegen) the penumbra:: targets its CMakeLists links."""
    modules = {}
    for cmake in sorted(root.glob("*/CMakeLists.txt")):
        text = cmake.read_text()
        match = MODULE_CALL.search(text)
        if not match:
            name = cmake.parent.name
            modules[name] = (set(LINKED_MODULE.findall(text)) - {name}, set())
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


def named_modules(line, modules):
    """The modules a line of code names, each with the text that names it."""
    found = {}
    for pattern in QUALIFIED_NAMES:
        for match in pattern.finditer(line):
            target = match.group(1)
            if target in modules and target not in found:
                found[target] = " ".join(match.group(0).split()).rstrip(" {;")
    return found


def check(root, rules):
    problems = []
    modules = declared_dependencies(root)
    for module, (public, private) in modules.items():
        for dependency in sorted((public | private) - rules.allowed.get(module, set())):
            problems.append(f"{root / module / 'CMakeLists.txt'}: {module} must not depend on "
                            f"{dependency} (docs/CONTRIBUTING.md, Modules)")
    for folder in sorted(p for p in root.iterdir() if p.is_dir() and p.name in rules.modules):
        module = folder.name
        allowed = includable(module, modules)
        for path in sorted(folder.rglob("*")):
            if path.suffix not in {".hpp", ".cpp", ".h"}:
                continue
            text = path.read_text(errors="replace")
            for number, line in enumerate(code_of(text).splitlines(), 1):
                for target, named in named_modules(line, rules.modules).items():
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
                elif ((confined := confined_as(header, rules.confined)) and
                      module not in rules.confined[confined]):
                    owners = ", ".join(sorted(rules.confined[confined]))
                    problems.append(f"{path}:{number}: {module} includes {header}, which is "
                                    f"confined to {owners}")
    return problems


def confined_as(header, confined):
    """The key of `confined` that names `header` most closely ("boost/program_options" before
    "boost"), or None."""
    names = [key for key in confined
             if header == key or header.startswith(key + "/") or header.startswith(key + ".")]
    return max(names, key=len, default=None)


# Broken tables, each with what its error must say.
BROKEN_TABLES = [
    ("# Working on Penumbra\n", "no '## Modules' section"),
    ("## Modules\nText, then the next section.\n## Next\n", "section has no table"),
    ("## Modules\n| module | layer |\n|---|---|\n", "columns must be"),
    ("## Modules\n| module | layer | responsibility | allowed dependencies | confined third-party "
     "headers |\n|---|---|---|---|---|\n| `base` | 0 | the bottom | – | – |\n"
     "| `volume` | 1 | volumes | base | – |\n", "'base' in the allowed dependencies column"),
    ("## Modules\n| module | layer | responsibility | allowed dependencies | confined third-party "
     "headers |\n|---|---|---|---|---|\n| `base` | 0 | the bottom | `volume` | – |\n"
     "| `volume` | 1 | volumes | `base` | – |\n", "dependencies point down or beside"),
    ("## Modules\n| module | layer | responsibility | allowed dependencies | confined third-party "
     "headers |\n|---|---|---|---|---|\n| `base` | 0 | the bottom | `scene` | – |\n",
     "which has no row"),
    ("## Modules\n| module | layer | responsibility | allowed dependencies | confined third-party "
     "headers |\n|---|---|---|---|---|\n| `a` | 1 | one | `b` | – |\n| `b` | 1 | two | `a` | – |\n",
     "go round: a -> b -> a"),
    ("## Modules\n| module | layer | responsibility | allowed dependencies | confined third-party "
     "headers |\n|---|---|---|---|---|\n| `base` | low | the bottom | – | – |\n",
     "layer 'low' is not a whole number"),
]


def self_test():
    """Plants one violation of each kind in a small tree, checked by the repository's table; each
    must be reported. Then each broken table must be refused with its error."""
    failures = []
    for text, error in BROKEN_TABLES:
        try:
            parse_rules(text, "table.md")
            failures.append(f"a table read although '{error}'")
        except TableError as refused:
            if error not in str(refused):
                failures.append(f"'{refused}' does not say '{error}'")
    rules = read_rules(TABLE)
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
        found = "\n".join(check(root, rules))
        expected = [
            "session includes penumbra/gpu/context.hpp",  # render links gpu PRIVATE
            "session includes OpenImageIO/imageio.h",      # confined to imageio
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
        if missing or unexpected or failures:
            print("self-test failed\nmissing: %s\nunexpected: %s\nbroken tables: %s" %
                  (missing, unexpected, failures))
            return 1
        print("self-test: every planted violation found, nothing else; every broken table "
              "refused")
        return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", type=pathlib.Path, help="the server/ folder")
    parser.add_argument("--table", type=pathlib.Path, default=TABLE,
                        help="the file whose Modules section holds the module table")
    parser.add_argument("--self-test", action="store_true")
    args = parser.parse_args()
    try:
        if args.self_test:
            return self_test()
        if not args.root:
            parser.error("--root or --self-test")
        rules = read_rules(args.table)
    except TableError as error:
        print(f"check_layering: {error}", file=sys.stderr)
        return 2
    problems = check(args.root, rules)
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
