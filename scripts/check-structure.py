#!/usr/bin/python3
"""The tree's structural limits (issue #12), one line per violation:

  - no source file under src/, include/ or cli/ over 800 lines;
  - no function over 120 lines, unless the comment lines just above it say
    why: `// glint:long-function: <reason>` (a hot kernel whose length is
    its speed);
  - no include cycle between the folders of src/glint (A includes B and B
    includes A, or longer: io -> image -> io).

Exit 0 when the tree keeps all three, 1 otherwise. Function bodies are found
by a heuristic: comments and literals blanked, then a '{' at namespace or
class level whose declaration ends in ')' (plus const, noexcept, override,
-> type...) and does not start with if/for/while/switch/catch opens one.

  scripts/check-structure.py [--root DIR] [--max-file-lines N] [--max-function-lines N]
"""
import argparse
import os
import re
import sys

SOURCE_DIRS = ("src", "include", "cli")
EXTENSIONS = (".h", ".hpp", ".cpp", ".cc", ".cxx", ".inl")
EXCEPTION_MARK = "glint:long-function:"
CONTROL = re.compile(r"^\s*(?:else\s+)?(?:if|for|while|switch|catch|return|case)\b")
FUNCTION_HEAD = re.compile(
    r"\)\s*(?:const\b|noexcept\b(?:\s*\([^()]*\))?|override\b|final\b|mutable\b|&&|&|"
    r"->\s*[\w:<>,\s*&]+?|\s)*$")
LAMBDA_HEAD = re.compile(r"\]\s*(?:\([^()]*(?:\([^()]*\)[^()]*)*\))?\s*(?:mutable\b|constexpr\b|noexcept\b|->[^{;]*|\s)*$")


def source_files(root):
    for top in SOURCE_DIRS:
        for folder, dirs, names in os.walk(os.path.join(root, top)):
            dirs.sort()
            for name in sorted(names):
                if name.endswith(EXTENSIONS):
                    yield os.path.join(folder, name)


def blank_comments_and_literals(text):
    """The text with comments, string and character literals replaced by
    spaces (newlines kept, so offsets and line numbers still match)."""
    out = list(text)
    i, n = 0, len(text)

    def blank(a, b):
        for k in range(a, b):
            if out[k] != "\n":
                out[k] = " "

    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            blank(i, j)
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            blank(i, j)
            i = j
        elif c == "R" and text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^()\\\s]{0,16})\(', text[i:])
            if not m:
                i += 1
                continue
            end = text.find(")" + m.group(1) + '"', i)
            j = n if end < 0 else end + len(m.group(1)) + 2
            blank(i + 1, j)
            i = j
        elif c in "\"'":
            # A digit separator (1'000'000) is no character literal.
            if c == "'" and i > 0 and text[i - 1].isalnum() and i + 1 < n and text[i + 1].isalnum():
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            blank(i + 1, min(j, n))
            i = j + 1
        else:
            i += 1
    return "".join(out)


def strip_preprocessor(code):
    # Directives (and their continuations) are no declarations.
    lines = code.split("\n")
    continued = False
    for k, line in enumerate(lines):
        if continued or line.lstrip().startswith("#"):
            continued = line.rstrip().endswith("\\")
            lines[k] = " " * len(line)
    return "\n".join(lines)


def long_functions(path, limit):
    with open(path, encoding="utf-8", errors="replace") as f:
        original = f.read()
    code = strip_preprocessor(blank_comments_and_literals(original))
    original_lines = original.split("\n")
    line_starts = [0]
    for k, ch in enumerate(code):
        if ch == "\n":
            line_starts.append(k + 1)

    def line_of(offset):
        lo, hi = 0, len(line_starts) - 1
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if line_starts[mid] <= offset:
                lo = mid
            else:
                hi = mid - 1
        return lo + 1

    depth = 0
    function_depth = None  # depth of the open function body's brace
    start = None
    head_start = 0  # offset just after the last ';', '{' or '}'
    for k, ch in enumerate(code):
        if ch == "{":
            if function_depth is None:
                head = code[head_start:k]
                flat = " ".join(head.split())
                is_function = (FUNCTION_HEAD.search(flat) and not CONTROL.match(flat) and not LAMBDA_HEAD.search(flat)
                               and "=" not in flat.split("(")[0])
                if is_function:
                    function_depth = depth
                    first = head_start + (len(head) - len(head.lstrip()))
                    start = (line_of(first), line_of(k), flat.split("(")[0].split()[-1] if "(" in flat else "?")
            depth += 1
            head_start = k + 1
        elif ch == "}":
            depth -= 1
            if function_depth is not None and depth == function_depth:
                head_line, brace_line, name = start
                end_line = line_of(k)
                length = end_line - head_line + 1
                marked = any(EXCEPTION_MARK in original_lines[i - 1]
                             for i in range(max(1, head_line - 3), brace_line + 1))
                if length > limit and not marked:
                    yield head_line, name, length
                function_depth = None
            head_start = k + 1
        elif ch == ";":
            head_start = k + 1


def folder_of(root, path):
    rel = os.path.relpath(path, os.path.join(root, "src", "glint"))
    parts = rel.split(os.sep)
    return parts[0] if len(parts) > 1 and not rel.startswith("..") else None


INCLUDE = re.compile(r'^\s*#\s*include\s+"glint/([^"/]+)/[^"]+"', re.M)


def include_cycles(root):
    edges = {}  # (a, b) -> first file of a that includes b
    for path in source_files(root):
        a = folder_of(root, path)
        if a is None:
            continue
        with open(path, encoding="utf-8", errors="replace") as f:
            for b in INCLUDE.findall(f.read()):
                if b != a:
                    edges.setdefault((a, b), os.path.relpath(path, root))
    graph = {}
    for a, b in edges:
        graph.setdefault(a, set()).add(b)
        graph.setdefault(b, set())
    # Tarjan's strongly connected components: every one with two or more
    # folders holds a cycle.
    index, low, on_stack, stack, components = {}, {}, set(), [], []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                components.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    problems = []
    for component in components:
        inside = sorted((a, b) for (a, b) in edges if a in component and b in component)
        detail = "; ".join(f"{a} -> {b} ({edges[(a, b)]})" for a, b in inside)
        problems.append(f"include cycle between folders {', '.join(component)}: {detail}")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    parser.add_argument("--max-file-lines", type=int, default=800)
    parser.add_argument("--max-function-lines", type=int, default=120)
    args = parser.parse_args()
    root = os.path.abspath(args.root)
    problems = []
    for path in source_files(root):
        rel = os.path.relpath(path, root)
        with open(path, encoding="utf-8", errors="replace") as f:
            lines = f.read().count("\n")
        if lines > args.max_file_lines:
            problems.append(f"{rel}: {lines} lines (limit {args.max_file_lines})")
        for line, name, length in long_functions(path, args.max_function_lines):
            problems.append(f"{rel}:{line}: function '{name}' is {length} lines (limit {args.max_function_lines}; "
                            f"a hot kernel may say why with '// {EXCEPTION_MARK} <reason>' above it)")
    problems.extend(include_cycles(root))
    for p in problems:
        print(p)
    print(f"check-structure: {len(problems)} problem{'s' if len(problems) != 1 else ''}", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
