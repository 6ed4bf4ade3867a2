#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The size check (issue 34): no C++ file of the library or the programs above 800 lines, no
function above 150 lines.

Walks libshadow/ (every component, whatever its folders) and tools/, reads each C++ source and
header, and fails listing `file:line name length` for every file longer than MAX_FILE_LINES and
every function (free function, member function, lambda at namespace or class scope) whose
definition, from the first line of its signature to its closing brace, spans more than
MAX_FUNCTION_LINES. Lambdas and local classes inside a function count as part of that function.

Functions are found by a brace-matching scan on the text with comments, string and character
literals (raw strings too) and preprocessor lines blanked out: a `{` at namespace or class scope
opens a namespace, a class, an initializer or a function body, told apart by what precedes it.

A few files or functions may be longer for a named reason: EXCEPTIONS below, each with a one-line
reason. An exception that no longer matches anything too long is reported too (remove it), so the
list stays short and true.

Usage: check_sizes.py [REPOSITORY_ROOT]   (default: the repository holding this script)
       check_sizes.py --self-test          (the scanner and the checks on small made-up sources)
Exit status: 0 clean, 1 sizes over the limits (or stale exceptions), 2 usage error.
"""

import os
import re
import sys

MAX_FILE_LINES = 800
MAX_FUNCTION_LINES = 150

# The folders scanned, relative to the repository root.
SCANNED = ("libshadow", "tools")

# Allowed longer: a path suffix ("tools/x.cpp" matches any path ending in /tools/x.cpp, so the key
# survives folder moves) for a whole file, or "path suffix:function name" for one function,
# mapped to the reason. Keep it short; each entry is a debt with its reason.
EXCEPTIONS = {}  # none left: issue 34 moved run_series_in into the library and made one scheduler

SOURCE_SUFFIXES = (".hpp", ".cpp", ".h", ".hh", ".cc", ".cxx", ".hxx", ".inl", ".ipp", ".tpp")


def source_files(root):
    for folder, dirs, files in os.walk(root):
        dirs.sort()
        for name in sorted(files):
            if name.endswith(SOURCE_SUFFIXES):
                yield os.path.join(folder, name)


def blank(text):
    """`text` with comments, string and character literals and preprocessor lines replaced by
    spaces (string literals keep their quotes, so `extern "C"` stays readable); newlines are
    kept so that offsets map to the same lines."""
    out = []
    i, n = 0, len(text)
    at_line_start = True  # only whitespace since the last newline
    while i < n:
        c = text[i]
        if c == "\n":
            out.append(c)
            i += 1
            at_line_start = True
            continue
        if at_line_start and c == "#":
            # A preprocessor line, with its backslash continuations (and comments within).
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    out.append(" \n")
                    i += 2
                    continue
                if text.startswith("/*", i):
                    end = text.find("*/", i + 2)
                    end = n if end < 0 else end + 2
                    out.append(re.sub(r"[^\n]", " ", text[i:end]))
                    i = end
                    continue
                out.append(" ")
                i += 1
            continue
        if not c.isspace():
            at_line_start = False
        if text.startswith("//", i):
            end = text.find("\n", i)
            end = n if end < 0 else end
            out.append(" " * (end - i))
            i = end
            continue
        if text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
            continue
        if c == '"':
            # Raw string: R"delim( ... )delim", with an optional u8/u/U/L prefix before the R.
            prefix = re.search(r"(?:\b|(?<=[^\w]))(?:u8|u|U|L)?R$", text[max(0, i - 3):i])
            if prefix and (i - len(prefix.group(0)) == 0 or not (text[i - len(prefix.group(0)) - 1].isalnum()
                                                               or text[i - len(prefix.group(0)) - 1] == "_")):
                open_paren = text.find("(", i + 1)
                delim = text[i + 1:open_paren]
                end = text.find(")" + delim + '"', open_paren + 1)
                end = n if end < 0 else end + len(delim) + 2
                out.append('"' + re.sub(r"[^\n]", " ", text[i + 1:end - 1]) + '"')
                i = end
                continue
            j = i + 1
            while j < n and text[j] != '"' and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            end = min(j + 1, n)
            out.append('"' + " " * (end - i - 2) + ('"' if end - i >= 2 else ""))
            i = end
            continue
        if c == "'":
            # A digit separator (1'000) or a character literal ('x', u8'x').
            k = i
            while k > 0 and (text[k - 1].isalnum() or text[k - 1] in "_'"):
                k -= 1
            if k < i and text[k].isdigit():
                out.append(c)
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != "'" and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            end = min(j + 1, n)
            out.append("'" + " " * (end - i - 2) + ("'" if end - i >= 2 else ""))
            i = end
            continue
        out.append(c)
        i += 1
    return "".join(out)


SCOPE_HEAD = re.compile(r"^(?:(?:inline\s+)?namespace\b|extern\s*\"\s*\"\s*$)")
TYPE_HEAD = re.compile(r"^(?:typedef\s+)?(?:\[\[[^\]]*\]\]\s*)?(?:class|struct|union|enum)\b")
ACCESS = re.compile(r"^(?:(?:public|private|protected)\s*:(?!:)\s*)+")
QUALIFIERS = re.compile(r"^(?:\s|const\b|volatile\b|noexcept\b|override\b|final\b|mutable\b|try\b"
                        r"|constexpr\b|&&|&|->.*)*$", re.DOTALL)


def strip_template(head):
    """`head` without leading `template <...>` clauses (balanced angle brackets)."""
    while True:
        m = re.match(r"template\s*<", head)
        if not m:
            return head
        depth, i = 1, m.end()
        while i < len(head) and depth:
            if head[i] == "<":
                depth += 1
            elif head[i] == ">":
                depth -= 1
            i += 1
        head = head[i:].lstrip()


def top_level_parens(head):
    """[(open, close)] offsets of the parenthesised groups of `head` at depth 0."""
    groups, depth, start = [], 0, None
    for i, c in enumerate(head):
        if c == "(":
            if depth == 0:
                start = i
            depth += 1
        elif c == ")" and depth:
            depth -= 1
            if depth == 0:
                groups.append((start, i))
    return groups


def function_name(head):
    """The name of the function whose signature is `head`, e.g. `Evaluator::evaluate`,
    `operator()`, `run (lambda)`."""
    head = " ".join(head.split())
    lam = re.search(r"([\w:]+)\s*=\s*\[[^\]]*\]\s*(?:\(|\{|$|mutable)", head)
    if lam:
        return lam.group(1) + " (lambda)"
    op = re.search(r"((?:[\w~]+::)*operator\s*(?:\(\s*\)|\[\s*\]|[^\s(\w]+|\w+[\w\s:<>*&]*?))\s*\(", head)
    if op:
        return op.group(1).replace(" ", "")
    m = re.search(r"((?:[\w~]+(?:<[^()]*>)?::)*~?\w+)\s*\(", head)
    return m.group(1) if m else head[:40]


def scan_functions(text):
    """[(first line, last line, name)] for each function body of C++ `text` (already blanked)."""
    line_of = []
    line = 1
    for c in text:
        line_of.append(line)
        if c == "\n":
            line += 1
    line_of.append(line)

    def matching(i):
        """Offset of the `}` closing the `{` at i (or the end of the text)."""
        depth = 0
        for j in range(i, len(text)):
            if text[j] == "{":
                depth += 1
            elif text[j] == "}":
                depth -= 1
                if depth == 0:
                    return j
        return len(text) - 1

    functions = []

    def scope(start, end):
        """Scans namespace or class scope text[start:end] (no enclosing braces)."""
        head_start = start
        i = start
        while i < end:
            c = text[i]
            if c in ";}":
                head_start = i + 1
            elif c == "{":
                raw = text[head_start:i]
                head = ACCESS.sub("", raw.strip())
                head = strip_template(head)
                close = matching(i)
                skip_head = 0
                if SCOPE_HEAD.match(head) or (TYPE_HEAD.match(head) and not head.rstrip().endswith(")")):
                    if TYPE_HEAD.match(head) and re.match(r"^(?:typedef\s+)?enum\b", head):
                        pass  # enumerators: nothing to scan
                    else:
                        scope(i + 1, close)
                else:
                    groups = top_level_parens(head)
                    if groups:
                        after = head[groups[-1][1] + 1:]
                        init_list = re.search(r"\)\s*(?:noexcept\s*)?:(?!:)", head)
                        before = head.rstrip()[-1:] if head.strip() else ""
                        if init_list and (before.isalnum() or before in "_>"):
                            # a member's brace initializer inside a constructor's init list
                            i = close + 1
                            continue
                        if QUALIFIERS.match(after) or init_list:
                            first = head_start + len(raw) - len(raw.lstrip())
                            # the signature starts after any access specifier
                            access = ACCESS.match(raw.strip())
                            if access:
                                first += len(access.group(0))
                            first_line = line_of[first]
                            functions.append((first_line, line_of[close], function_name(head)))
                        # else: an initializer that calls something, e.g. `T x = f() {`? skip it
                    # else: an initializer (`= {...}`, `x{...}`): skip, not a function
                i = close
                head_start = close + 1
                # `struct X {...} x;` or `= {...};`: the statement ends at the `;`
            i += 1

    scope(0, len(text))
    return functions


def check_file(path, rel):
    """[(rel path, line, name, length, kind)] of what in `path` is over the limits."""
    with open(path, encoding="utf-8", errors="replace") as f:
        text = f.read()
    over = []
    lines = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
    if lines > MAX_FILE_LINES:
        over.append((rel, 1, "(file)", lines, "file"))
    for first, last, name in scan_functions(blank(text)):
        length = last - first + 1
        if length > MAX_FUNCTION_LINES:
            over.append((rel, first, name, length, "function"))
    return over


def exception_for(rel, name, kind, exceptions):
    for key in exceptions:
        path, _, function = key.partition(":")
        if not ("/" + rel).endswith("/" + path):
            continue
        if (kind == "file" and not function) or (kind == "function" and function == name):
            return key
    return None


def check(repo, exceptions=None):
    """(problems, notes): problems fail the check, notes list the excepted items."""
    exceptions = EXCEPTIONS if exceptions is None else exceptions
    problems, notes, used = [], [], set()
    for folder in SCANNED:
        root = os.path.join(repo, folder)
        if not os.path.isdir(root):
            continue
        for path in source_files(root):
            rel = os.path.relpath(path, repo).replace(os.sep, "/")
            for rel_path, line, name, length, kind in check_file(path, rel):
                limit = MAX_FILE_LINES if kind == "file" else MAX_FUNCTION_LINES
                where = f"{rel_path}:{line} {name} {length} lines"
                key = exception_for(rel_path, name, kind, exceptions)
                if key:
                    used.add(key)
                    notes.append(f"{where} (excepted: {exceptions[key]})")
                else:
                    problems.append(f"{where} (a {kind} above {limit} lines)")
    for key in sorted(set(exceptions) - used):
        problems.append(f"exception '{key}' matches nothing too long: remove it from EXCEPTIONS "
                        f"in tests/check_sizes.py")
    return problems, notes


def self_test():
    """Runs the scanner and the checks on small made-up sources."""
    import tempfile

    failures = []

    def expect(what, got, want):
        if got != want:
            failures.append(f"{what}: expected {want}, got {got}")

    def names(source):
        return [(first, last, name) for first, last, name in scan_functions(blank(source))]

    expect("a free function", names("int f(int x)\n{\n  return x;\n}\n"), [(1, 4, "f")])
    expect("namespaces, a class, members and an out-of-class definition", names(
        "namespace a { namespace {\n"
        "class C : public B {\n"
        "public:\n"
        "  int g() const { return 1; }\n"
        "  int x{3};\n"
        "  std::vector<int> v = {1, 2};\n"
        "};\n"
        "} }\n"
        "int a::C::h() const noexcept\n{\n  if (x) { return 2; }\n  return 3;\n}\n"),
        [(4, 4, "g"), (9, 13, "a::C::h")])
    expect("lambdas inside a function belong to it", names(
        "void run() {\n  auto f = [&](int i) {\n    return i;\n  };\n  f(1);\n}\n"), [(1, 6, "run")])
    expect("a lambda at namespace scope", names(
        "const auto twice = [](int i) {\n  return 2 * i;\n};\n"), [(1, 3, "twice (lambda)")])
    expect("braces in strings, characters and comments", names(
        'void s() {\n  const char* t = "}{";\n  char c = \'}\';\n  // }\n  /* { */\n'
        '  auto r = R"x(})x";\n}\nvoid u() {}\n'), [(1, 7, "s"), (8, 8, "u")])
    expect("digit separators are not character literals", names(
        "int k() {\n  return 1'000'000;\n}\nint m() { return 0; }\n"), [(1, 3, "k"), (4, 4, "m")])
    expect("a constructor's init list with brace initializers", names(
        "S::S(int a)\n  : a_(a), b_{a, 2}, c_{}\n{\n  go();\n}\n"), [(1, 5, "S::S")])
    expect("templates, operators, trailing return types", names(
        "template <class T, class U>\nauto add(T t, U u) -> decltype(t + u)\n{\n  return t + u;\n}\n"
        "bool operator==(const P& a, const P& b) { return a.x == b.x; }\n"
        "struct F { int operator()(int i) const { return i; } };\n"),
        [(1, 5, "add"), (6, 6, "operator=="), (7, 7, "operator()")])
    expect("preprocessor lines and enums", names(
        "#define BODY { \\\n  }\nenum class E { a, b };\n#if X\nvoid p() {\n#endif\n}\n"),
        [(5, 7, "p")])
    expect("aggregate initializers at namespace scope are not functions", names(
        "const std::array<int, 2> table = {\n  1,\n  2,\n};\nint w[] {1};\n"), [])
    expect("a test macro body is a function", names(
        "TEST(Suite, Name) {\n  EXPECT_EQ(1, 1);\n}\n"), [(1, 3, "TEST")])

    scratch = tempfile.TemporaryDirectory(prefix="check-sizes-")  # removed when the self-test ends

    def tree(files):
        root = tempfile.mkdtemp(dir=scratch.name)
        for rel, text in files.items():
            path = os.path.join(root, rel)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
        return root

    def body(lines):
        return "void f()\n{\n" + "  x();\n" * (lines - 3) + "}\n"

    long_file = "".join(f"int v{i} = {i};\n" for i in range(MAX_FILE_LINES + 1))
    clean = {
        "libshadow/compute/src/exact/a.cpp": body(MAX_FUNCTION_LINES),
        "libshadow/src/fast/b.cpp": "int x;\n" * MAX_FILE_LINES,
        "tools/shadow/c.cpp": "int main() { return 0; }\n",
        "tests/long_test.cpp": long_file,  # tests/ is not scanned
    }
    problems, _ = check(tree(clean), {})
    expect("a clean tree", problems, [])
    cases = {
        "a long function": ({"libshadow/compute/src/exact/a.cpp": body(MAX_FUNCTION_LINES + 1)},
                            {}, ["libshadow/compute/src/exact/a.cpp:1 f 151 lines"]),
        "a long file in tools": ({"tools/bench/d.cpp": long_file}, {}, ["tools/bench/d.cpp:1 (file) 801 lines"]),
        "an excepted function": ({"tools/shadow/e.cpp": body(200)}, {"shadow/e.cpp:f": "why"}, []),
        "an excepted file": ({"libshadow/io/src/g.cpp": long_file}, {"io/src/g.cpp": "why"}, []),
        "a stale exception": ({}, {"tools/h.cpp:f": "why"}, ["exception 'tools/h.cpp:f' matches nothing"]),
    }
    for name, (files, exceptions, expected) in cases.items():
        problems, _ = check(tree({**clean, **files}), exceptions)
        if len(problems) != len(expected) or not all(p.startswith(e) for p, e in zip(problems, expected)):
            failures.append(f"{name}: expected {expected}, got {problems}")
    for f in failures:
        print("check_sizes self-test: FAIL " + f)
    if not failures:
        print("check_sizes self-test: ok (the scanner finds the functions of 11 made-up sources; "
              f"{len(cases)} kinds of finding)")
    return 1 if failures else 0


def main(argv):
    if argv[1:] == ["--self-test"]:
        return self_test()
    if len(argv) > 2 or (len(argv) == 2 and argv[1].startswith("-")):
        print("usage: check_sizes.py [REPOSITORY_ROOT] | --self-test", file=sys.stderr)
        return 2
    repo = os.path.abspath(argv[1] if len(argv) == 2 else os.path.join(os.path.dirname(__file__), ".."))
    if not os.path.isdir(os.path.join(repo, "libshadow")):
        print(f"check_sizes: {repo}: no libshadow/ folder (give the repository root)", file=sys.stderr)
        return 2
    problems, notes = check(repo)
    for n in notes:
        print("  " + n)
    if problems:
        print(f"check_sizes: {len(problems)} size problem(s) (files at most {MAX_FILE_LINES} lines, "
              f"functions at most {MAX_FUNCTION_LINES}):")
        for p in problems:
            print("  " + p)
        return 1
    print(f"check_sizes: ok (no file above {MAX_FILE_LINES} lines, no function above "
          f"{MAX_FUNCTION_LINES} lines in {', '.join(SCANNED)}, {len(notes)} named exception(s))")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
