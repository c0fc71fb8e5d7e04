#!/usr/bin/env python3
"""Lists every function of src/, src_cuda/ and samples/ (C++ and CUDA) longer than LIMIT lines, from the line of its
name to its closing brace (a lambda counts inside its function); exits 1 when there is one. The full range's CUDA
path kernel is exempt for now: its body gets split into named steps with the rewrite of its arithmetic (less work per
cell), as the windows' kernel was (WindowWalk).

    tools/function_lengths.py [--all] [--limit N]     (run from anywhere; --all lists every function, longest first)

A scanner, not a parser: comments, strings and preprocessor lines are blanked, and a brace at namespace or class level
opens a function when the text since the last ';', '{' or '}' has an argument list and is no class, struct, union,
enum, namespace or initializer (' = {')."""
import os
import re
import signal
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FOLDERS = ("src", "src_cuda", "samples")
EXTENSIONS = (".cpp", ".hpp", ".cu", ".cuh", ".h")
EXEMPT = {"pathKernel"}
LIMIT = 120
ATTRIBUTE = re.compile(r"\b__launch_bounds__\s*\([^()]*\)|\b__attribute__\s*\(\([^()]*(?:\([^()]*\)[^()]*)*\)\)")
TEMPLATE = re.compile(r"\btemplate\s*<[^<>]*(?:<[^<>]*>[^<>]*)*>")
SCOPE = re.compile(r"\b(class|struct|union|enum|namespace)\b")
NAME = re.compile(r"(~?[A-Za-z_]\w*(?:\s*::\s*~?[A-Za-z_]\w*)*|operator\s*(?:\(\s*\)|[^\s(]+))\s*(?:<[^()]*>)?\s*$")


def blank(text):
    """text with comments, string and character literals and preprocessor lines replaced by spaces (newlines kept)."""
    out = []
    i, n = 0, len(text)
    line_start = True
    while i < n:
        c = text[i]
        if line_start and c == "#":   # a directive, with its continuation lines
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    out.append(" \n")
                    i += 2
                    continue
                out.append(" ")
                i += 1
            continue
        if c == "\n":
            line_start = True
            out.append(c)
            i += 1
            continue
        if not c.isspace():
            line_start = False
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == 'R' and text.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i)
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c in "\"'" and not (c == "'" and i > 0 and text[i - 1].isalnum()):   # 1'000 is a digit separator
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            j += 1
            out.append(" " * (j - i))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(text):
    """(name, first line, last line) of each function defined in text."""
    # attributes with argument lists are not the function's own
    code = ATTRIBUTE.sub(lambda m: " " * len(m.group(0)), blank(text))
    result = []
    stack = []   # per open brace: True for a namespace, class or extern block (functions may open inside)
    stmt = 0     # where the text before the next brace began
    i = 0
    while i < len(code):
        c = code[i]
        if c in ";}":
            if c == "}" and stack:
                stack.pop()
            stmt = i + 1
        elif c == "{":
            head = code[stmt:i]
            bare = TEMPLATE.sub(" ", head)   # 'template <class T>' declares no class
            if stack and not stack[-1]:
                stack.append(False)   # a block inside a function
            elif SCOPE.search(bare.split("(")[0]) or re.search(r"\bextern\s*$", bare) or not bare.strip() \
                    or re.search(r"=\s*$", bare) or "(" not in bare:
                stack.append(True)
            else:
                name, line = signature(code, stmt, head)
                end = closing(code, i)
                result.append((name, line, code.count("\n", 0, end) + 1))
                i = end
                stmt = i + 1
                continue
            stmt = i + 1
        i += 1
    return result


def signature(code, stmt, head):
    """The function's name and the line it is on: the identifier before the first top-level '('."""
    depth = 0
    for k, ch in enumerate(head):
        if ch == "(" and depth == 0:
            if re.search(r"\boperator\s*$", head[:k]):   # operator(): its name holds the first '('
                continue
            m = NAME.search(head[:k])
            if m:
                return re.sub(r"\s+", "", m.group(1)), code.count("\n", 0, stmt + m.start(1)) + 1
            break
        depth += ch == "<"
        depth -= ch == ">" and depth > 0
    line = code.count("\n", 0, stmt + len(head) - len(head.lstrip())) + 1
    return head.strip().split("(")[0].split()[-1] if head.strip() else "?", line


def closing(code, i):
    depth = 0
    for j in range(i, len(code)):
        depth += code[j] == "{"
        depth -= code[j] == "}"
        if depth == 0:
            return j
    return len(code) - 1


def main():
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)   # --all | head
    args = sys.argv[1:]
    limit = int(args[args.index("--limit") + 1]) if "--limit" in args else LIMIT
    rows = []
    for folder in FOLDERS:
        for base, _, files in os.walk(os.path.join(ROOT, folder)):
            for f in sorted(files):
                if f.endswith(EXTENSIONS):
                    path = os.path.join(base, f)
                    with open(path, encoding="utf-8") as fh:
                        for name, first, last in functions(fh.read()):
                            rows.append((last - first + 1, os.path.relpath(path, ROOT), first, name))
    rows.sort(key=lambda r: (-r[0], r[1], r[2]))
    if "--all" in args:
        for n, path, line, name in rows:
            print("%5d  %s:%d  %s" % (n, path, line, name))
        return 0
    long_ = [r for r in rows if r[0] > limit and r[3].split("::")[-1] not in EXEMPT]
    for n, path, line, name in long_:
        print("%s:%d: %s is %d lines (limit %d)" % (path, line, name, n, limit))
    if long_:
        print("function_lengths: %d functions longer than %d lines; split them into named steps" % (len(long_), limit))
        return 1
    print("function_lengths: no function longer than %d lines (%d functions, %s exempt)"
          % (limit, len(rows), ", ".join(sorted(EXEMPT))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
