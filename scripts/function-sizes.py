#!/usr/bin/env python3
"""Function sizes in sylva's C++ sources: median, 90th percentile and the
functions longer than a limit (80 lines by default).

Counts the lines of each function body, from the line that opens it to its
closing brace, in files formatted by clang-format-14 --style=file (a function
or lambda body at any depth; a class body is not a function). It is a
lexical count, not a parser: good for trends and for finding long functions.

  python3 scripts/function-sizes.py [--limit 80] [--list] [DIR...]
"""
import argparse
import os
import re
import statistics
import sys

SOURCE_DIRS = ["core", "reconstruct", "simulate", "mesh", "sketch", "ui", "datasets", "tests"]
# A line that ends a function head: a closing parenthesis (maybe followed by
# qualifiers, an initialiser list or a trailing return type) and an opening brace.
HEAD = re.compile(r"\)\s*(const|override|final|noexcept|mutable|->[^{]*|\s)*(:[^;]*)?\{\s*$")
NOT_FUNCTION = re.compile(r"^\s*(if|for|while|switch|catch|else|do)\b|\b(if|for|while|switch|catch)\s*\(")


def strip(line):
    line = re.sub(r'"(\\.|[^"\\])*"', '""', line)
    line = re.sub(r"'(\\.|[^'\\])*'", "''", line)
    return line.split("//", 1)[0]


def functions(path):
    """Yields (name, first line, length in lines) of each function in the file."""
    with open(path, encoding="utf-8", errors="replace") as f:
        lines = [strip(l) for l in f]
    stack = []  # (is_function, name, start line)
    depth_text = ""
    for number, line in enumerate(lines, 1):
        for k, ch in enumerate(line):
            if ch == "{":
                head = line[: k + 1]
                # The head may span lines: join the previous few to see ") {" with its name.
                context = " ".join(l.strip() for l in lines[max(0, number - 6): number - 1]) + " " + head
                is_function = bool(HEAD.search(head.rstrip() if head.rstrip().endswith("{") else head)) \
                    and not NOT_FUNCTION.search(head) and "class " not in head and "struct " not in head \
                    and "namespace" not in head and "enum " not in head
                name = ""
                if is_function:
                    m = re.findall(r"([~\w:<>]+)\s*\(", context)
                    name = m[-1] if m else "?"
                    # A lambda or a call like Foo(x, [&] { ... }) is not what we count separately.
                    if name in ("", "?") or context.rstrip().endswith("] {"):
                        is_function = False
                stack.append((is_function, name, number))
            elif ch == "}":
                if not stack:
                    continue
                is_function, name, start = stack.pop()
                if is_function and not any(f for f, _, _ in stack):
                    yield name, start, number - start + 1


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("dirs", nargs="*", help="folders to scan (default: sylva's source folders)")
    parser.add_argument("--limit", type=int, default=80, help="list functions longer than this")
    parser.add_argument("--list", action="store_true", help="list the long functions")
    parser.add_argument("--no-tests", action="store_true", help="leave out *_test.cc and tests/")
    args = parser.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    dirs = args.dirs or [os.path.join(root, d) for d in SOURCE_DIRS]
    sizes, long = [], []
    for top in dirs:
        for base, _, files in os.walk(top):
            if args.no_tests and (os.sep + "tests" in base or base.endswith("tests")):
                continue
            for file in sorted(files):
                if not file.endswith((".cc", ".h")) or (args.no_tests and file.endswith("_test.cc")):
                    continue
                path = os.path.join(base, file)
                for name, start, length in functions(path):
                    sizes.append(length)
                    if length > args.limit:
                        long.append((length, os.path.relpath(path, root), start, name))
    if not sizes:
        sys.exit("function-sizes: no functions found")
    sizes.sort()
    p90 = sizes[min(len(sizes) - 1, int(0.9 * len(sizes)))]
    print(f"functions {len(sizes)}  median {statistics.median(sizes):.0f} lines  "
          f"90th percentile {p90} lines  over {args.limit} lines: {len(long)}")
    if args.list:
        for length, path, start, name in sorted(long, reverse=True):
            print(f"  {length:4d}  {path}:{start}  {name}")


if __name__ == "__main__":
    main()
