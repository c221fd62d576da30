#!/usr/bin/python3
"""The product's longest functions: every function or method body in engine/, app/, capi/, web/src/ and python/
longer than a limit, longest first, with a count over 80 and over 120 lines.

  /usr/bin/python3 tools/function_lengths.py [--over 80]

A function is found by its signature starting at the file's or a class's indentation (0 or 2 spaces) and its
closing brace at the same indentation, as clang-format lays them out; lambdas and nested classes count with the
function that holds them."""
import argparse
import pathlib
import re

SIGNATURE = re.compile(r"^\s*[A-Za-z_][\w:<>,&* ]*[\w>]\s*[*&]?\s*[\w:~]+\(")
NOT_A_FUNCTION = ("if", "for", "while", "switch", "else", "return", "namespace", "class", "struct", "using",
                  "static_assert")


def lengths(path):
    lines = path.read_text(encoding="utf-8", errors="replace").split("\n")
    i = 0
    while i < len(lines):
        line = lines[i]
        indent = len(line) - len(line.lstrip())
        if indent in (0, 2) and SIGNATURE.match(line) and not line.lstrip().startswith(NOT_A_FUNCTION):
            j, signature = i, line
            while not signature.rstrip().endswith(("{", ";")) and j + 1 < len(lines) and j - i < 6:
                j += 1
                signature += " " + lines[j].strip()
            if signature.rstrip().endswith("{"):
                k = j + 1
                while k < len(lines) and not (lines[k].startswith(" " * indent + "}")
                                              and len(lines[k]) - len(lines[k].lstrip()) == indent):
                    k += 1
                yield k - i + 1, i + 1, line.strip()
                i = k + 1
                continue
        i += 1


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--over", type=int, default=80, help="list the functions longer than this many lines")
    arguments = parser.parse_args()
    root = pathlib.Path(__file__).resolve().parent.parent
    found = []
    for folder in ("engine", "app", "capi", "web/src", "python"):
        for path in sorted((root / folder).rglob("*.cpp")):
            for length, line, signature in lengths(path):
                found.append((length, f"{path.relative_to(root)}:{line}", signature[:90]))
    found.sort(reverse=True)
    print(f"{sum(1 for f in found if f[0] > 80)} functions over 80 lines, {sum(1 for f in found if f[0] > 120)} over 120")
    for length, where, signature in found:
        if length > arguments.over:
            print(f"{length:5d}  {where}  {signature}")


main()
