#!/usr/bin/env python3
"""List C++ function bodies longer than N lines (python3 only).

Usage: long_functions.py [ROOT] [--max-lines N] | --self-test
Scans *.cpp/*.cc/*.h/*.hpp under ROOT (default: the repository holding this
script), skipping tests/, bench/, docs/results/ (study programs), build*/,
third_party/, vendored and hidden directories. A function is a `{` at
namespace or class level whose preceding text looks like a signature (`...)`
optionally followed by const, override, noexcept, `-> T` or a constructor's
initialiser list); its length counts the lines from the signature's `{` to
the matching `}`. Comments, strings, character literals and preprocessor
lines are blanked first, so braces in them do not count. Prints
`file:line name lines` for each one longer than N (default 150) and exits 1
if there is any, 0 if none, 2 on bad arguments.
--self-test checks the heuristic on a snippet (braces in comments, strings,
raw strings, digit separators, init lists, lambdas, enums, initialisers).
"""
import os
import re
import sys

SKIP_DIRS = {"tests", "bench", "third_party", "thirdparty", "external", "extern",
             "vendor", "vendored", "deps", "node_modules"}
# Measurement programs kept with their results, like bench/ studies.
SKIP_PATHS = {"docs/results"}
EXTENSIONS = (".cpp", ".cc", ".cxx", ".h", ".hpp", ".hh")

# Text after a signature's closing parenthesis that still makes it one.
TRAILER = re.compile(
    r"\)\s*(?:(?:const|volatile|override|final|mutable|noexcept(?:\s*\([^()]*\))?"
    r"|&&|&|->\s*[\w:<>,\s*&\[\]]+)\s*)*$")
SCOPE = re.compile(r"\b(?:namespace|class|struct|union)\b[^()]*$|\bextern\s+\"C\"\s*$")
NOT_FUNCTION = re.compile(r"\b(?:if|for|while|switch|catch|do|else|try|return|enum)\b")


def blank(text):
    """Blank comments, string/char literals and preprocessor lines, keeping
    newlines so that offsets keep their line numbers."""
    out = []
    i, n = 0, len(text)
    line_start = True
    while i < n:
        c = text[i]
        if line_start and c in " \t":
            out.append(c)
            i += 1
            continue
        if line_start and c == "#":
            # Preprocessor line, with backslash continuations.
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
            line_start = True
            out.append(c)
            i += 1
        elif text.startswith("//", i):
            while i < n and text[i] != "\n":
                out.append(" ")
                i += 1
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == '"' and re.search(r"(?:^|[^\w])(?:u8|u|U|L)?R$", text[max(0, i - 3):i]):
            # Raw string literal R"delim( ... )delim".
            k = text.find("(", i)
            delim = text[i + 1:k]
            j = text.find(")" + delim + '"', k)
            j = n if j < 0 else j + len(delim) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == '"' or (c == "'" and not is_digit_separator(text, i)):
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(c + " " * (j - i - 2) + c if j - i >= 2 else c)
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def is_digit_separator(text, i):
    """True when the ' at i separates digits of a number (1'000, 0xFF'FF)."""
    j = i
    while j > 0 and (text[j - 1].isalnum() or text[j - 1] in "'."):
        j -= 1
    return j < i and text[j].isdigit()


def strip_templates(header):
    """The header without its `template <...>` parameter lists."""
    out, k = [], 0
    for m in re.finditer(r"\btemplate\s*<", header):
        if m.start() < k:
            continue
        out.append(header[k:m.start()])
        depth, j = 1, m.end()
        while j < len(header) and depth:
            depth += {"<": 1, ">": -1}.get(header[j], 0)
            j += 1
        k = j
    out.append(header[k:])
    return "".join(out)


def function_name(header):
    """The name before the signature's first top-level '(' (best effort)."""
    depth_angle = 0
    for k, c in enumerate(header):
        if c == "<":
            depth_angle += 1
        elif c == ">":
            depth_angle = max(0, depth_angle - 1)
        elif c == "(" and depth_angle == 0:
            m = re.search(r"((?:[\w~]+\s*::\s*)*(?:operator\s*\S+?|~?\w+))\s*$", header[:k])
            if m:
                return re.sub(r"\s+", "", m.group(1))
    return "?"


def is_signature(header):
    h = header.strip()
    if not h or "=" in re.sub(r"operator\s*[^\s(]*", "", h.split("(")[0]):
        return False  # an initialiser (`T x = {`, `auto f = [] {`), not a definition
    if NOT_FUNCTION.search(h.split("(")[0]):
        return False
    if TRAILER.search(h):
        return True
    # Constructor with an initialiser list: `X::X(a) : m_(a), n_{b}`
    return bool(re.search(r"\)\s*(?:noexcept\s*)?:\s*[\w:]+\s*[({]", h))


def long_functions(path, max_lines):
    return long_functions_in_text(open(path, encoding="utf-8", errors="replace").read(), max_lines)


def long_functions_in_text(text, max_lines):
    code = blank(text)
    found = []
    # Stack of block kinds: "scope" (namespace/class: may hold functions),
    # "function", "init" (a brace initialiser inside a signature's init list)
    # and "other" (enum bodies, initialisers).
    stack = []
    header_start = 0
    fn_start = None  # (offset of '{', line of name, name)
    for i, c in enumerate(code):
        in_scope = all(k in ("scope",) for k in stack)
        if c == "{":
            if not in_scope:
                stack.append("other")
                continue
            header = strip_templates(code[header_start:i])
            if SCOPE.search(header.split("(")[0]):
                stack.append("scope")
                header_start = i + 1
            elif is_signature(header):
                stack.append("function")
                name = function_name(header)
                raw = code[header_start:i]
                lead = len(raw) - len(raw.lstrip())
                name_line = code.count("\n", 0, header_start + lead) + 1
                fn_start = (i, name_line, name)
            elif re.search(r"\)\s*(?:noexcept\s*)?:", header) and re.search(r"\w\s*$", header):
                stack.append("init")  # `m_{a}` inside an initialiser list
            else:
                stack.append("other")
        elif c == "}":
            if not stack:
                continue  # unbalanced (macro trickery): ignore
            kind = stack.pop()
            if kind == "function" and all(k == "scope" for k in stack):
                start, name_line, name = fn_start
                lines = code.count("\n", start, i) + 1
                if lines > max_lines:
                    found.append((name_line, name, lines))
                header_start = i + 1
            elif kind == "scope":
                header_start = i + 1
            elif kind == "other" and all(k == "scope" for k in stack):
                header_start = i + 1
        elif c == ";" and in_scope:
            header_start = i + 1
    return found


SELF_TEST = r"""
namespace a {
template <class T>
struct Box {
  int size() const noexcept {
    return 1;
  }
};
const char* kShader = R"(
  void main() { if (x) { } }
)";
Foo::Foo(int x) : x_{x}, y_(x) {
  // } a brace in a comment
  auto f = [&] { return '}'; };
  int n = 1'000;
}
enum class E { A, B };
const int kTable[] = {1, 2, 3};
auto Bar::get() const -> int {
  return 2;
}
}  // namespace a
"""


def self_test():
    """Checks the heuristic on SELF_TEST: every function found, with its
    line and length, and nothing else."""
    got = long_functions_in_text(SELF_TEST, 0)
    want = [(5, "size", 3), (12, "Foo::Foo", 5), (19, "Bar::get", 3)]
    if got != want:
        print("long_functions.py self-test: expected %r, got %r" % (want, got), file=sys.stderr)
        return 1
    return 0


def source_files(root):
    for dirpath, dirnames, filenames in os.walk(root):
        rel = os.path.relpath(dirpath, root).replace(os.sep, "/")
        dirnames[:] = sorted(
            d for d in dirnames
            if not d.startswith(".") and d not in SKIP_DIRS and not d.startswith("build")
            and (rel + "/" + d).lstrip("./") not in SKIP_PATHS)
        for f in sorted(filenames):
            if f.endswith(EXTENSIONS):
                yield os.path.join(dirpath, f)


def main(argv):
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    max_lines = 150
    args = list(argv[1:])
    while args:
        a = args.pop(0)
        if a == "--max-lines":
            if not args or not args[0].isdigit() or int(args[0]) < 1:
                print("long_functions.py: --max-lines expects a positive integer, got %r"
                      % (args[0] if args else None), file=sys.stderr)
                return 2
            max_lines = int(args.pop(0))
        elif a == "--self-test":
            return self_test()
        elif a in ("-h", "--help"):
            print(__doc__)
            return 0
        elif a.startswith("-"):
            print("long_functions.py: unknown option %r (expected --max-lines N)" % a,
                  file=sys.stderr)
            return 2
        else:
            root = a
    if not os.path.isdir(root):
        print("long_functions.py: %s is not a directory" % root, file=sys.stderr)
        return 2
    bad = 0
    for path in source_files(root):
        for line, name, lines in long_functions(path, max_lines):
            print("%s:%d %s %d" % (os.path.relpath(path, root), line, name, lines))
            bad += 1
    if bad:
        print("%d function(s) longer than %d lines: split them into named helpers"
              % (bad, max_lines), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
