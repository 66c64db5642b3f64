#!/usr/bin/env python3
"""Size budget of sylva's C++ sources: functions and files that grew past what a reader can hold.

  tools/size_budget.py check              fail (exit 1) on a function over 120 lines or a file
                                          over 800 lines that tools/size-allowlist.txt does not
                                          list at that size or more; fail on an allow-list entry
                                          that is stale (gone, or now under the limit) so the
                                          list only shrinks
  tools/size_budget.py list [--over N]    every function longer than N lines (default 80)
  tools/size_budget.py files [--over N]   every file longer than N lines (default 500)
  tools/size_budget.py allowlist          print the allow-list today's tree needs

Why hand-written (docs/contributing.md names it): clang-tidy's readability-function-size parses
every translation unit (minutes on two cores, with the whole include path) and pmccabe's parser
gives up on lambdas and attributes. This counter needs only brace structure: comments, strings
and preprocessor lines are blanked, then every '{' is classified by the text before it as a
scope (namespace, class, struct, union, enum, extern "C"), a function body (the header's last
top-level ')' followed only by qualifiers, a trailing return type or a constructor's member
initialisers) or anything else (an initialiser). A function's length runs from the first line of
its declaration to its closing brace, both included; lambdas and local classes count toward the
function that holds them.
"""
import os
import re
import subprocess
import sys

FUNCTION_LIMIT = 120
FILE_LIMIT = 800
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ALLOWLIST = os.path.join(ROOT, "tools", "size-allowlist.txt")
SKIP_PREFIXES = ("third_party/", "out/")


def sources():
    out = subprocess.run(["git", "ls-files", "*.cpp", "*.h", "*.cc", "*.hpp"], cwd=ROOT,
                         capture_output=True, text=True, check=True).stdout.split()
    return sorted(p for p in out if not p.startswith(SKIP_PREFIXES) and os.path.exists(os.path.join(ROOT, p)))


def blank(text):
    """The text with comments, string and character literals and preprocessor lines replaced by
    spaces (newlines kept, so line numbers stay)."""
    out = []
    i, n = 0, len(text)
    line_start = True
    while i < n:
        c = text[i]
        if line_start and c in " \t":
            out.append(c)
            i += 1
            continue
        if line_start and c == "#":  # a preprocessor line, with its continuations
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    out.append(" \n")
                    i += 2
                    continue
                out.append(" ")
                i += 1
            continue
        line_start = False
        if c == "\n":
            out.append(c)
            line_start = True
            i += 1
        elif text.startswith("//", i):
            while i < n and text[i] != "\n":
                out.append(" ")
                i += 1
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
        elif c == "R" and i + 1 < n and text[i + 1] == '"' and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^()\\ ]{0,16})\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            close = ")" + m.group(1) + '"'
            end = text.find(close, i + m.end())
            end = n if end < 0 else end + len(close)
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
        elif c == '"' or (c == "'" and not (i > 0 and text[i - 1].isalnum())):
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(c + " " * (j - i - 2) + (c if j - i >= 2 else ""))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


SCOPE_RE = re.compile(r"(^|[^\w])(namespace|class|struct|union|enum|extern)([^\w]|$)")
QUALIFIERS_RE = re.compile(
    r"^(\s|const\b|noexcept\b|override\b|final\b|mutable\b|volatile\b|&|&&|"
    r"try\b|requires\b.*|->.*)*$", re.S)


def last_top_level_paren(header):
    """Index just past the last ')' that closes a top-level '(' in `header`, or -1."""
    depth, end = 0, -1
    for k, ch in enumerate(header):
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth == 0:
                end = k + 1
    return end


def classify(header):
    h = header.strip()
    if not h:
        return "other"
    first_paren = h.find("(")
    head_words = h if first_paren < 0 else h[:first_paren]
    if SCOPE_RE.search(head_words) and "=" not in head_words:
        return "scope"
    if first_paren < 0:
        return "other"
    end = last_top_level_paren(h)
    if end < 0:
        return "other"
    rest = h[end:]
    if QUALIFIERS_RE.match(rest):
        # `x = f(a) {` cannot be; `auto f = [](int a) {` is a lambda at namespace scope: count it.
        return "function"
    # A constructor's member initialisers: `) : a_(x), b_{y}` before the body.
    if re.match(r"^\s*(noexcept\b\s*(\([^)]*\))?\s*)?:[^:]", rest):
        return "function"
    return "other"


def functions(path):
    """[(first line, last line, name)] of every function body in the file, outermost only."""
    with open(os.path.join(ROOT, path), encoding="utf-8", errors="replace") as f:
        text = blank(f.read())
    result = []
    stack = []  # entries: ("scope"|"function"|"other", start line, name)
    header_start = 0  # index where the current header began
    line = 1
    in_function = 0
    for k, ch in enumerate(text):
        if ch == "\n":
            line += 1
            continue
        if in_function:
            if ch == "{":
                stack.append(("inner", line, ""))
            elif ch == "}":
                kind, start, name = stack.pop()
                if kind == "function":
                    in_function -= 1
                    result.append((start, line, name))
                    header_start = k + 1
            continue
        if ch == ";":
            header_start = k + 1
        elif ch == "{":
            header = text[header_start:k]
            kind = classify(header)
            if kind == "function":
                lead = len(header) - len(header.lstrip())
                start_line = line - header[lead:].count("\n")
                test = re.search(r"\b(?:TEST|TEST_F|TEST_P)\s*\(\s*(\w+)\s*,\s*(\w+)", header)
                paren = header.find("(")
                name = re.findall(r"[\w:~<>=!+\-*/\[\]]+", header[:paren])
                label = f"{test.group(1)}.{test.group(2)}" if test else (name[-1] if name else "?")
                stack.append(("function", start_line, label))
                in_function += 1
            else:
                stack.append((kind, line, ""))
                if kind == "scope":
                    header_start = k + 1
        elif ch == "}":
            if stack:
                kind, _, _ = stack.pop()
                if kind == "scope":
                    header_start = k + 1
    return result


def file_lines(path):
    with open(os.path.join(ROOT, path), "rb") as f:
        return f.read().count(b"\n")


def long_functions(limit):
    rows = []
    for p in sources():
        for start, end, name in functions(p):
            n = end - start + 1
            if n > limit:
                rows.append((n, p, start, name))
    return sorted(rows, key=lambda r: (-r[0], r[1], r[2]))


def long_files(limit):
    rows = [(file_lines(p), p) for p in sources()]
    return sorted([r for r in rows if r[0] > limit], key=lambda r: (-r[0], r[1]))


def read_allowlist():
    allowed = {}
    if not os.path.exists(ALLOWLIST):
        return allowed
    with open(ALLOWLIST, encoding="utf-8") as f:
        for raw in f:
            s = raw.split("#", 1)[0].strip()
            if not s:
                continue
            size, where = s.split(None, 1)
            allowed[where.strip()] = int(size)
    return allowed


def current_entries():
    entries = {}
    for n, p, start, name in long_functions(FUNCTION_LIMIT):
        entries[f"{p} {name}"] = max(n, entries.get(f"{p} {name}", 0))
    for n, p in long_files(FILE_LIMIT):
        entries[f"{p}"] = n
    return entries


def check():
    allowed = read_allowlist()
    entries = current_entries()
    problems = []
    for where, n in sorted(entries.items()):
        kind = "file" if " " not in where else "function"
        limit = FILE_LIMIT if kind == "file" else FUNCTION_LIMIT
        if where not in allowed:
            problems.append(f"{where}: {kind} of {n} lines (limit {limit}); split it "
                            f"(tools/size-allowlist.txt only shrinks)")
        elif n > allowed[where]:
            problems.append(f"{where}: {kind} grew to {n} lines (allowed {allowed[where]}); split it")
    for where, n in sorted(allowed.items()):
        if where not in entries:
            problems.append(f"{where}: allowed at {n} lines but now within the limit: "
                            f"remove its line from tools/size-allowlist.txt")
        elif entries[where] < n:
            problems.append(f"{where}: allowed at {n} lines but now {entries[where]}: "
                            f"lower its line in tools/size-allowlist.txt")
    for p in problems:
        print("size-budget: " + p)
    if not problems:
        print(f"size-budget: ok ({len(entries)} allowed exceptions; functions <= {FUNCTION_LIMIT}, "
              f"files <= {FILE_LIMIT} lines)")
    return 1 if problems else 0


def main(argv):
    cmd = argv[1] if len(argv) > 1 else "check"
    over = None
    if "--over" in argv:
        over = int(argv[argv.index("--over") + 1])
    if cmd == "check":
        return check()
    if cmd == "list":
        rows = long_functions(over if over is not None else 80)
        for n, p, start, name in rows:
            print(f"{n:5d}  {p}:{start}  {name}")
        print(f"{len(rows)} functions")
        return 0
    if cmd == "files":
        rows = long_files(over if over is not None else 500)
        for n, p in rows:
            print(f"{n:5d}  {p}")
        print(f"{len(rows)} files")
        return 0
    if cmd == "allowlist":
        for where, n in sorted(current_entries().items()):
            print(f"{n} {where}")
        return 0
    print(__doc__)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
