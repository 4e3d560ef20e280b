#!/usr/bin/env python3
"""The library's shape, as docs/architecture.md states it: folders are layers and a header includes only
from its own layer or the layers before it in the table (never gapfe.hpp, never a folder that does not
exist); no header over 400 lines; no function over 150 lines (a brace count over the sources, tests aside);
no two headers with one file name; the command's program includes only app/command.hpp of the library and
names nothing of it but gapfe::app.

    python3 tests/check_layers.py SOURCE_DIR"""
import os
import re
import sys

LAYERS = [["core"], ["element", "kinematics", "material", "mesh", "solver"], ["problem"], ["contact"],
          ["assembly"], ["post"], ["driver"], ["input"], ["output"], ["run"], ["app"]]
RANK = {folder: k for k, group in enumerate(LAYERS) for folder in group}
MAX_HEADER_LINES, MAX_FUNCTION_LINES = 400, 150
SIGNATURE = re.compile(r"^(\s*)(?:template <.*>\s*)?(?:inline |static |constexpr |explicit |friend )*"
                       r"[\w:<>,\s*&\[\]]+?\b(\w+)\s*\(")


def function_lengths(lines):
    """(length, first line, name) of every function body: a signature line, then the line ending in '{'
    within eight lines, to the brace that closes it."""
    i = 0
    while i < len(lines):
        m = SIGNATURE.match(lines[i])
        stripped = lines[i].strip()
        if m and not stripped.startswith(("//", "return", "if", "for", "while", "switch", "else", "#")) \
                and not lines[i].rstrip().endswith(";") and m.group(2) not in ("class", "struct", "namespace"):
            def code(n):  # the line without a trailing // comment
                return lines[n].split("//")[0].rstrip()
            j = i
            while j < len(lines) and j < i + 8 and not code(j).endswith(("{", ";")):
                j += 1
            if j < len(lines) and code(j).endswith("{"):
                depth, k = 0, j
                while k < len(lines):
                    depth += code(k).count("{") - code(k).count("}")
                    if depth <= 0:
                        break
                    k += 1
                yield k - i + 1, i + 1, m.group(2)
                if k - i + 1 > MAX_FUNCTION_LINES:
                    i = k
        i += 1


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    include = os.path.join(root, "include", "gapfe")
    problems, names = [], {}
    for folder in sorted(os.listdir(include)):
        path = os.path.join(include, folder)
        if not os.path.isdir(path):
            continue
        if folder not in RANK:
            problems.append(f"include/gapfe/{folder}/: a folder in no layer (docs/architecture.md)")
            continue
        for f in sorted(os.listdir(path)):
            where = f"include/gapfe/{folder}/{f}"
            names.setdefault(f, []).append(where)
            lines = open(os.path.join(path, f)).read().split("\n")
            if len(lines) - 1 > MAX_HEADER_LINES:
                problems.append(f"{where}: {len(lines) - 1} lines (at most {MAX_HEADER_LINES})")
            for n, line in enumerate(lines, 1):
                m = re.match(r'\s*#\s*include\s*[<"]gapfe/([\w.]+)(/?)', line)
                if not m:
                    continue
                target = m.group(1)
                if not m.group(2):  # gapfe/gapfe.hpp or gapfe/version.hpp
                    if target != "version.hpp":
                        problems.append(f"{where}:{n}: includes gapfe/{target} (the umbrella is for programs)")
                elif target not in RANK:
                    problems.append(f"{where}:{n}: includes gapfe/{target}/, a folder in no layer")
                elif RANK[target] > RANK[folder]:
                    problems.append(f"{where}:{n}: includes gapfe/{target}/ from a layer above {folder}/")
    for f, where in names.items():
        if len(where) > 1:
            problems.append(f"one file name in two folders: {', '.join(where)}")
    for base in ("include", "examples"):
        for dirpath, _, files in os.walk(os.path.join(root, base)):
            for f in files:
                if f.endswith((".hpp", ".cpp")):
                    p = os.path.join(dirpath, f)
                    for length, line, name in function_lengths(open(p).read().split("\n")):
                        if length > MAX_FUNCTION_LINES:
                            problems.append(f"{os.path.relpath(p, root)}:{line}: {name} is {length} lines "
                                            f"(at most {MAX_FUNCTION_LINES})")
    main_text = open(os.path.join(root, "examples", "gapfe", "main.cpp")).read()
    for inc in re.findall(r'#\s*include\s*[<"](gapfe/[^>"]+)', main_text):
        if inc != "gapfe/app/command.hpp":
            problems.append(f"examples/gapfe/main.cpp includes {inc}: the program sees the library's command only")
    for name in set(re.findall(r"\bgapfe::(\w+)", main_text)) - {"app"}:
        problems.append(f"examples/gapfe/main.cpp names gapfe::{name}: the program calls gapfe::app only")
    if re.search(r"using\s+namespace\s+gapfe|namespace\s+\w+\s*=\s*gapfe", main_text):
        problems.append("examples/gapfe/main.cpp brings gapfe's names in wholesale")
    for p in problems:
        print(p)
    print(f"{len(problems)} problem(s) in the library's shape")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
